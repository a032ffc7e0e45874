//! How far behind its link the unit is: the bytes written to its UART that its emulator (or
//! the companion) has not yet read, as the kernel's socket table shows them at the unit's end
//! of the loopback TCP link (Linux's `/proc/net/tcp`; unmeasured elsewhere).
//!
//! QEMU's UART models take one byte at a time, so an emulated unit reads its link at a rate of
//! its own; where SITL runs faster than the wall clock the stream can outrun it, and the unit
//! then steers on states that grow older by the second.

use std::net::{SocketAddr, TcpStream};

/// The unit's end of the router's TCP link to it, as `/proc/net/tcp` names it.
pub struct UnitEnd {
    /// `local_address` and `rem_address` of the unit's socket: the router's peer and the
    /// router's own address.
    local: String,
    remote: String,
}

impl UnitEnd {
    /// The unit's end of `stream` (the router's side); `None` for a link that is not IPv4.
    pub fn of(stream: &TcpStream) -> Option<UnitEnd> {
        let (peer, ours) = (stream.peer_addr().ok()?, stream.local_addr().ok()?);
        Some(UnitEnd {
            local: proc_address(peer)?,
            remote: proc_address(ours)?,
        })
    }

    /// The bytes queued at the unit's end, unread; `None` where the table is not there.
    pub fn queued(&self) -> Option<u64> {
        let table = std::fs::read_to_string("/proc/net/tcp").ok()?;
        queued_in(&table, &self.local, &self.remote)
    }
}

/// `address` as `/proc/net/tcp` prints it: the IPv4 address as the native-endian number of its
/// network-order bytes, then the port, both in upper-case hex.
fn proc_address(address: SocketAddr) -> Option<String> {
    match address {
        SocketAddr::V4(a) => Some(format!(
            "{:08X}:{:04X}",
            u32::from_ne_bytes(a.ip().octets()),
            a.port()
        )),
        SocketAddr::V6(_) => None,
    }
}

/// The `rx_queue` of the row of `table` (`/proc/net/tcp`'s text) from `local` to `remote`.
fn queued_in(table: &str, local: &str, remote: &str) -> Option<u64> {
    table.lines().skip(1).find_map(|line| {
        let mut fields = line.split_whitespace().skip(1);
        let (l, r, _state, queues) = (
            fields.next()?,
            fields.next()?,
            fields.next()?,
            fields.next()?,
        );
        if l != local || r != remote {
            return None;
        }
        let (_, rx) = queues.split_once(':')?;
        u64::from_str_radix(rx, 16).ok()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = "  sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  timeout inode
   0: 0100007F:87F5 00000000:0000 0A 00000000:00000000 00:00000000 00000000     0        0 1 1 0 100 0 0 10 0
   1: 0100007F:87F5 0100007F:8172 01 00000000:00009C40 00:00000000 00000000     0        0 2 1 0 20 4 30 10 -1
   2: 0100007F:8172 0100007F:87F5 01 00000010:00000000 00:00000000 00000000     0        0 3 1 0 20 4 30 10 -1
";

    #[test]
    fn the_unread_bytes_are_read_off_the_units_row() {
        let (unit, router) = ("0100007F:87F5", "0100007F:8172");
        assert_eq!(queued_in(TABLE, unit, router), Some(40_000));
        assert_eq!(queued_in(TABLE, router, unit), Some(0));
        assert_eq!(queued_in(TABLE, unit, "0100007F:0001"), None);
    }

    #[test]
    fn a_loopback_address_is_written_as_the_kernel_writes_it() {
        let a: SocketAddr = "127.0.0.1:34805".parse().unwrap();
        let expected = if cfg!(target_endian = "little") {
            "0100007F:87F5"
        } else {
            "7F000001:87F5"
        };
        assert_eq!(proc_address(a).as_deref(), Some(expected));
    }

    #[test]
    fn a_live_link_reads_its_own_queue() {
        use std::io::Write;
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let mut router = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (_unit, _) = listener.accept().unwrap();
        router.write_all(&[0x55; 1000]).unwrap();
        let end = UnitEnd::of(&router).unwrap();
        // Loopback delivers at once; the unit reads nothing, so all 1000 bytes wait.
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(2);
        let mut seen = end.queued();
        while seen != Some(1000) && std::time::Instant::now() < deadline && seen.is_some() {
            seen = end.queued();
        }
        if std::path::Path::new("/proc/net/tcp").exists() {
            assert_eq!(seen, Some(1000));
        }
    }
}
