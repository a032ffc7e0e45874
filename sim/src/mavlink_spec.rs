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
/// VFR_HUD: an autopilot's airspeed, ground speed, altitude and climb.
pub const VFR_HUD: (u32, u8) = (74, 20);

/// VFR_HUD's payload in wire order: airspeed, ground speed, altitude and climb (f32), then
/// heading (i16) and throttle (u16); only the airspeed (m/s) set.
pub fn vfr_hud_payload(airspeed: f32) -> Vec<u8> {
    let mut p = airspeed.to_le_bytes().to_vec();
    p.extend_from_slice(&[0u8; 16]);
    p
}

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
pub fn v2(sequence: u8, system: u8, message: (u32, u8), payload: &[u8], signed: bool) -> Vec<u8> {
    v2_from(sequence, (system, 1), message, payload, signed)
}

/// A MAVLink 2 frame from (`system`, `component`).
pub fn v2_from(
    sequence: u8,
    (system, component): (u8, u8),
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
        component,
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
    position_payload_at(123_456, lat, lon, vx, vy, hdg)
}

/// GLOBAL_POSITION_INT's payload as [`position_payload`], stamped `time_boot_ms`.
pub fn position_payload_at(
    time_boot_ms: u32,
    lat: i32,
    lon: i32,
    vx: i16,
    vy: i16,
    hdg: u16,
) -> Vec<u8> {
    position_payload_in_air(time_boot_ms, [lat, lon], [vx, vy, 5], hdg, 10_000)
}

/// GLOBAL_POSITION_INT's payload with the height above home `relative_alt` (mm) and the
/// velocity north, east and down (cm/s).
pub fn position_payload_in_air(
    time_boot_ms: u32,
    [lat, lon]: [i32; 2],
    velocity: [i16; 3],
    hdg: u16,
    relative_alt: i32,
) -> Vec<u8> {
    let mut p = Vec::new();
    p.extend_from_slice(&time_boot_ms.to_le_bytes());
    for v in [lat, lon, 500_000, relative_alt] {
        p.extend_from_slice(&v.to_le_bytes());
    }
    for v in velocity {
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
    p.extend(param_id(name));
    p.push(kind);
    p
}

/// PARAM_REQUEST_READ's payload in wire order: index (-1: by name), target, name.
pub fn param_request_read_payload(target: (u8, u8), name: &str, index: i16) -> Vec<u8> {
    let mut p = index.to_le_bytes().to_vec();
    p.extend([target.0, target.1]);
    p.extend(param_id(name));
    p
}

/// PARAM_REQUEST_LIST's payload: the target.
pub fn param_request_list_payload(target: (u8, u8)) -> Vec<u8> {
    vec![target.0, target.1]
}

/// A parameter name as MAVLink's 16-byte, zero-padded param_id.
fn param_id(name: &str) -> [u8; 16] {
    let mut id = [0_u8; 16];
    for (d, s) in id.iter_mut().zip(name.bytes()) {
        *d = s;
    }
    id
}

/// FOLLOW_TARGET's payload in wire order: timestamp and custom state (u64), lat, lon (degE7),
/// alt, vel (m/s, north-east-down), acc (zero), attitude quaternion (w, x, y, z), rates and
/// position covariance (zero), capability bits.
pub fn follow_target_payload(
    lat: i32,
    lon: i32,
    vel: [f32; 3],
    attitude: [f32; 4],
    capabilities: u8,
) -> Vec<u8> {
    let mut p = 5_000_u64.to_le_bytes().to_vec();
    p.extend(0_u64.to_le_bytes());
    p.extend(lat.to_le_bytes());
    p.extend(lon.to_le_bytes());
    p.extend(20.0_f32.to_le_bytes());
    for v in vel
        .iter()
        .chain(&[0.0; 3])
        .chain(&attitude)
        .chain(&[0.0; 6])
    {
        p.extend(v.to_le_bytes());
    }
    p.push(capabilities);
    p
}

/// (message id, CRC_EXTRA) of the messages the endpoint sends.
pub const PARAM_VALUE: (u32, u8) = (22, 220);
/// (message id, CRC_EXTRA).
pub const SET_ATTITUDE_TARGET: (u32, u8) = (82, 49);
/// (message id, CRC_EXTRA): the CRC over "SET_POSITION_TARGET_LOCAL_NED " and its fields'
/// types and names in wire order, as the specification defines it.
pub const SET_POSITION_TARGET_LOCAL_NED: (u32, u8) = (84, 143);
/// (message id, CRC_EXTRA).
pub const NAMED_VALUE_FLOAT: (u32, u8) = (251, 170);
/// (message id, CRC_EXTRA): the CRC over "NAMED_VALUE_INT " and "uint32_t time_boot_ms
/// int32_t value char name " with the name's length, 10.
pub const NAMED_VALUE_INT: (u32, u8) = (252, 44);
/// (message id, CRC_EXTRA).
pub const STATUSTEXT: (u32, u8) = (253, 83);

/// A MAVLink 2 frame read back: sender, message id and payload (zero-extended to `min_len`
/// by the reader of each message).
#[derive(Clone, Debug, PartialEq)]
pub struct Sent {
    /// Sender's system id.
    pub system: u8,
    /// Sender's component id.
    pub component: u8,
    /// Sequence number.
    pub sequence: u8,
    /// Message id.
    pub id: u32,
    /// The payload as sent (trailing zeros may be dropped).
    pub payload: Vec<u8>,
}

impl Sent {
    /// `len` payload bytes from `offset`, zero-extended past the end of the sent payload.
    pub fn bytes<const N: usize>(&self, offset: usize) -> [u8; N] {
        let mut out = [0_u8; N];
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.payload.get(offset + i).copied().unwrap_or(0);
        }
        out
    }
    /// An f32 field at `offset`.
    pub fn f32(&self, offset: usize) -> f32 {
        f32::from_le_bytes(self.bytes(offset))
    }
    /// An i32 field at `offset`.
    pub fn i32(&self, offset: usize) -> i32 {
        i32::from_le_bytes(self.bytes(offset))
    }
    /// A u16 field at `offset`.
    pub fn u16(&self, offset: usize) -> u16 {
        u16::from_le_bytes(self.bytes(offset))
    }
    /// A u8 field at `offset`.
    pub fn u8(&self, offset: usize) -> u8 {
        self.bytes::<1>(offset)[0]
    }
    /// A NUL-padded text field of `len` bytes at `offset`.
    pub fn text(&self, offset: usize, len: usize) -> String {
        (0..len)
            .map(|i| self.payload.get(offset + i).copied().unwrap_or(0))
            .take_while(|&b| b != 0)
            .map(char::from)
            .collect()
    }
}

/// Splits `stream` into MAVLink 2 frames, checking each checksum with the CRC_EXTRA `extras`
/// gives; an error for any byte outside a frame, an unknown id or a bad checksum.
pub fn read_v2(stream: &[u8], extras: &[(u32, u8)]) -> Result<Vec<Sent>, String> {
    let mut out = Vec::new();
    let mut at = 0;
    while at < stream.len() {
        let f = &stream[at..];
        if f[0] != 0xFD || f.len() < 12 {
            return Err(format!("no MAVLink 2 frame at byte {at}"));
        }
        let len = usize::from(f[1]);
        let total = 12 + len;
        if f.len() < total || f[2] != 0 {
            return Err(format!("truncated or flagged frame at byte {at}"));
        }
        let id = u32::from_le_bytes([f[7], f[8], f[9], 0]);
        let extra = extras
            .iter()
            .find(|(i, _)| *i == id)
            .map(|&(_, e)| e)
            .ok_or_else(|| format!("unexpected message id {id}"))?;
        let mut checked = f[1..10 + len].to_vec();
        checked.push(extra);
        if x25(&checked).to_le_bytes() != [f[10 + len], f[11 + len]] {
            return Err(format!("bad checksum on message {id} at byte {at}"));
        }
        out.push(Sent {
            system: f[5],
            component: f[6],
            sequence: f[4],
            id,
            payload: f[10..10 + len].to_vec(),
        });
        at += total;
    }
    Ok(out)
}

/// Every message id the endpoint sends, with its CRC_EXTRA.
pub const SENT_BY_ENDPOINT: [(u32, u8); 7] = [
    HEARTBEAT,
    PARAM_VALUE,
    SET_ATTITUDE_TARGET,
    SET_POSITION_TARGET_LOCAL_NED,
    NAMED_VALUE_FLOAT,
    NAMED_VALUE_INT,
    STATUSTEXT,
];
