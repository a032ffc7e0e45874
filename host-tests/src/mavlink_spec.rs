//! MAVLink frames written from the protocol's specification, independently of the `mavlink`
//! crate the firmware uses: the header layouts of MAVLink 1 and 2, the X.25 checksum with the
//! message's CRC_EXTRA, MAVLink 2's trailing-zero truncation and its 13-byte signature. The
//! endpoint's tests and the fuzz target's seeds are built with it.

/// (message id, CRC_EXTRA) from the common dialect's definitions.
pub const GLOBAL_POSITION_INT: (u32, u8) = (33, 104);
/// (message id, CRC_EXTRA).
pub const FOLLOW_TARGET: (u32, u8) = (144, 127);
/// (message id, CRC_EXTRA).
pub const PARAM_SET: (u32, u8) = (23, 168);
/// (message id, CRC_EXTRA).
pub const PARAM_REQUEST_READ: (u32, u8) = (20, 214);
/// (message id, CRC_EXTRA).
pub const PARAM_REQUEST_LIST: (u32, u8) = (21, 159);
/// (message id, CRC_EXTRA).
pub const HEARTBEAT: (u32, u8) = (0, 50);

/// X.25 (CRC-16/MCRF4XX) as the MAVLink specification gives it.
pub fn x25(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &b in bytes {
        let mut tmp = b ^ (crc & 0xFF) as u8;
        tmp ^= tmp << 4;
        crc = (crc >> 8) ^ (u16::from(tmp) << 8) ^ (u16::from(tmp) << 3) ^ (u16::from(tmp) >> 4);
    }
    crc
}

/// A MAVLink 2 frame from component 1 (trailing zero payload bytes dropped; 13 signature bytes
/// if `signed`).
pub fn v2(
    sequence: u8,
    system: u8,
    (id, extra): (u32, u8),
    payload: &[u8],
    signed: bool,
) -> Vec<u8> {
    let mut p = payload.to_vec();
    while p.len() > 1 && p.last() == Some(&0) {
        p.pop();
    }
    let id = id.to_le_bytes();
    let flags = u8::from(signed);
    let mut f = vec![
        0xFD,
        p.len() as u8,
        flags,
        0,
        sequence,
        system,
        1,
        id[0],
        id[1],
        id[2],
    ];
    f.extend_from_slice(&p);
    let mut checked = f[1..].to_vec();
    checked.push(extra);
    f.extend_from_slice(&x25(&checked).to_le_bytes());
    if signed {
        f.extend_from_slice(&[7; 13]);
    }
    f
}

/// A MAVLink 1 frame from component 1.
pub fn v1(sequence: u8, system: u8, (id, extra): (u32, u8), payload: &[u8]) -> Vec<u8> {
    let mut f = vec![0xFE, payload.len() as u8, sequence, system, 1, id as u8];
    f.extend_from_slice(payload);
    let mut checked = f[1..].to_vec();
    checked.push(extra);
    f.extend_from_slice(&x25(&checked).to_le_bytes());
    f
}

/// GLOBAL_POSITION_INT's payload in wire order (fields by size, then as declared): time 123.456
/// s, altitude 500 m (10 m relative), vz 5 cm/s, and the given lat, lon (degE7), vx, vy (cm/s)
/// and hdg (cdeg).
pub fn position_payload(lat: i32, lon: i32, vx: i16, vy: i16, hdg: u16) -> Vec<u8> {
    let mut p = Vec::new();
    p.extend_from_slice(&123_456_u32.to_le_bytes());
    for v in [lat, lon, 500_000, 10_000] {
        p.extend_from_slice(&v.to_le_bytes());
    }
    for v in [vx, vy, 5] {
        p.extend_from_slice(&v.to_le_bytes());
    }
    p.extend_from_slice(&hdg.to_le_bytes());
    p
}

/// PARAM_SET's payload in wire order: value, target system and component, the name (16 bytes,
/// zero-padded) and the type (9 = MAV_PARAM_TYPE_REAL32).
pub fn param_set_payload(target: (u8, u8), name: &str, value: f32, kind: u8) -> Vec<u8> {
    let mut p = value.to_le_bytes().to_vec();
    p.extend([target.0, target.1]);
    let mut id = [0_u8; 16];
    for (d, s) in id.iter_mut().zip(name.bytes()) {
        *d = s;
    }
    p.extend(id);
    p.push(kind);
    p
}
