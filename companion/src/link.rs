//! The byte links a companion computer reaches its autopilot over: a UDP port, a serial device
//! or a TCP connection. Each reads what has come within a few milliseconds and writes whole
//! buffers; none blocks the endpoint's clock for longer.

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream, UdpSocket};
use std::time::Duration;

/// How long a read waits for bytes: the endpoint's clock is polled at least this often.
pub const READ_WAIT: Duration = Duration::from_millis(5);

/// A link to the autopilot.
pub trait Link {
    /// Reads what has arrived (waiting up to [`READ_WAIT`]); 0 when nothing has.
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize>;
    /// Writes `bytes` whole (a UDP link: as one datagram, where it knows its peer).
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<()>;
}

/// Whether an error only says that nothing came in time.
fn nothing_came(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted
    )
}

/// Peers a UDP link answers at most: the autopilot, a ground station, a router or two.
pub const UDP_PEERS: usize = 8;

/// A UDP port bound to a local address (PX4's offboard link sends to 14540; ArduPilot's
/// `udpclient` outputs to a port). What the endpoint says goes to every address that has sent
/// to it, as a MAVLink router's UDP server does (the autopilot and a ground station both hear
/// the unit), the first [`UDP_PEERS`] of them; before any has, to the given peer, if any.
pub struct Udp {
    socket: UdpSocket,
    peers: Vec<SocketAddr>,
}

impl Udp {
    /// Binds `local`; `peer`, if given, is where to send before anyone has spoken.
    pub fn bind(local: SocketAddr, peer: Option<SocketAddr>) -> std::io::Result<Udp> {
        let socket = UdpSocket::bind(local)?;
        socket.set_read_timeout(Some(READ_WAIT))?;
        Ok(Udp {
            socket,
            peers: peer.into_iter().collect(),
        })
    }
}

impl Link for Udp {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self.socket.recv_from(buf) {
            Ok((n, from)) => {
                if !self.peers.contains(&from) && self.peers.len() < UDP_PEERS {
                    self.peers.push(from);
                }
                Ok(n)
            }
            // The port-unreachable report of a peer gone away, not a datagram.
            Err(e) if nothing_came(&e) || e.kind() == ErrorKind::ConnectionRefused => Ok(0),
            Err(e) => Err(e),
        }
    }

    fn write(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        // With no peer yet this sends nothing: what the endpoint says before anyone speaks is
        // its heartbeat, which the next one repeats.
        for peer in &self.peers {
            match self.socket.send_to(bytes, peer) {
                // A peer gone away (ICMP port unreachable) is not the link failing.
                Err(e) if e.kind() == ErrorKind::ConnectionRefused => {}
                other => other.map(|_| ())?,
            }
        }
        Ok(())
    }
}

/// A serial device (8N1, no flow control) or a TCP connection: a stream of bytes.
pub struct Stream<S> {
    stream: S,
    /// A read of 0 bytes means the peer closed it (TCP; a serial device may return 0).
    closes: bool,
}

/// Opens the serial device `path` at `baud`.
pub fn serial(path: &str, baud: u32) -> Result<Stream<Box<dyn serialport::SerialPort>>, String> {
    let port = serialport::new(path, baud)
        .timeout(READ_WAIT)
        .open()
        .map_err(|e| format!("{path}: {e}"))?;
    Ok(Stream {
        stream: port,
        closes: false,
    })
}

/// Connects to `address` over TCP (ArduPilot SITL's serial ports, a MAVLink router's TCP server).
pub fn tcp(address: SocketAddr) -> std::io::Result<Stream<TcpStream>> {
    let stream = TcpStream::connect(address)?;
    stream.set_read_timeout(Some(READ_WAIT))?;
    stream.set_nodelay(true)?;
    Ok(Stream {
        stream,
        closes: true,
    })
}

impl<S: Read + Write> Link for Stream<S> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self.stream.read(buf) {
            Ok(0) if self.closes => Err(ErrorKind::UnexpectedEof.into()),
            Ok(n) => Ok(n),
            Err(e) if nothing_came(&e) => Ok(0),
            Err(e) => Err(e),
        }
    }

    fn write(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.stream.write_all(bytes)
    }
}
