//! `twocars-companion`: the MAVLink guidance unit of the `*-mavlink` firmware images as a
//! Linux program, for a companion computer (a Raspberry Pi, a Jetson) beside the autopilot
//! rather than a spare MCU. The same `twocars::mavlink::Endpoint` runs over a UDP port, a
//! serial device or a TCP connection, on the host's monotonic clock; docs/companion.md.
//!
//! ```text
//! twocars-companion --udp 127.0.0.1:14540
//! twocars-companion --serial /dev/ttyAMA0 --baud 921600 --param TC_V_PM=3 --param TC_W_PM=0.47
//! ```

mod link;
mod params;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use clap::Parser;
use twocars::mavlink::params::index;
use twocars::mavlink::signing::{parse_key, timestamp_from_unix_us, LINK_ID};
use twocars::mavlink::Endpoint;

use link::Link;

/// The MAVLink guidance unit on a companion computer (docs/companion.md).
#[derive(Parser, Debug)]
#[command(version)]
struct Args {
    /// Bind this UDP address and answer every address that speaks to it (PX4's offboard
    /// link: 14540).
    #[arg(long, value_name = "ADDR:PORT", conflicts_with_all = ["serial", "tcp"])]
    udp: Option<SocketAddr>,
    /// With --udp: send here too, from the start (before anyone has spoken).
    #[arg(long, value_name = "ADDR:PORT", requires = "udp")]
    udp_peer: Option<SocketAddr>,
    /// A serial device to the autopilot's TELEM port (8N1, no flow control).
    #[arg(long, value_name = "DEVICE", conflicts_with = "tcp")]
    serial: Option<String>,
    /// The serial device's baud rate.
    #[arg(long, default_value_t = 921_600, requires = "serial")]
    baud: u32,
    /// Connect to this TCP address (ArduPilot SITL's SERIAL1 is 127.0.0.1:5762).
    #[arg(long, value_name = "ADDR:PORT")]
    tcp: Option<SocketAddr>,
    /// Sign and check every frame with this MAVLink 2 key (a file of 32 bytes or 64
    /// hexadecimal digits), the autopilot given the same one.
    #[arg(long, value_name = "FILE")]
    signing_key: Option<PathBuf>,
    /// Set a parameter before the first frame (TC_V_PM=3); repeatable. All of them, with
    /// those of --params, are checked and set as one set, so their order does not matter.
    /// Parameters live in memory: give them at each start.
    #[arg(long = "param", value_name = "NAME=VALUE", value_parser = parse_param)]
    params: Vec<(String, f32)>,
    /// Set the parameters of this file (the autopilots' .parm form: NAME VALUE or NAME,VALUE
    /// a line, # comments) before the first frame; --param values override them.
    #[arg(long = "params", value_name = "FILE")]
    params_file: Option<PathBuf>,
    /// Check the arguments and the parameters, print the parameters as set and exit, without
    /// opening the link.
    #[arg(long)]
    check: bool,
}

fn parse_param(text: &str) -> Result<(String, f32), String> {
    let (name, value) = text.split_once('=').ok_or("a parameter is NAME=VALUE")?;
    let value: f32 = value.trim().parse().map_err(|e| format!("{name}: {e}"))?;
    Ok((name.trim().to_string(), value))
}

/// The signing clock now: 10 us since 2015-01-01 UTC (MAVLink 2's signing epoch).
fn signing_clock_now() -> u64 {
    let since_unix = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    timestamp_from_unix_us(since_unix.as_micros() as u64)
}

/// The endpoint the arguments ask for: signing, then the parameters as one set.
fn endpoint(args: &Args) -> Result<Endpoint, String> {
    let mut endpoint = Endpoint::new();
    if let Some(path) = &args.signing_key {
        let file = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let key = parse_key(&file).ok_or(format!(
            "{}: a key file holds 32 bytes or 64 hexadecimal digits",
            path.display()
        ))?;
        endpoint = endpoint.with_signing(key, LINK_ID, signing_clock_now());
    }
    let mut given = match &args.params_file {
        Some(path) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            params::parse_parm(&text).map_err(|e| format!("{}: {e}", path.display()))?
        }
        None => Vec::new(),
    };
    given.extend(args.params.iter().cloned());
    params::set(&mut endpoint, &given)?;
    Ok(endpoint)
}

/// The link the arguments name.
fn open(args: &Args) -> Result<(Box<dyn Link>, String), String> {
    if let Some(local) = args.udp {
        let udp = link::Udp::bind(local, args.udp_peer).map_err(|e| format!("{local}: {e}"))?;
        return Ok((Box::new(udp), format!("UDP {local}")));
    }
    if let Some(path) = &args.serial {
        let port = link::serial(path, args.baud)?;
        return Ok((Box::new(port), format!("{path} at {} baud", args.baud)));
    }
    if let Some(address) = args.tcp {
        let stream = link::tcp(address).map_err(|e| format!("{address}: {e}"))?;
        return Ok((Box::new(stream), format!("TCP {address}")));
    }
    Err("give one link: --udp ADDR:PORT, --serial DEVICE or --tcp ADDR:PORT".to_string())
}

/// Feeds the link's bytes to the endpoint on the monotonic clock and sends what it says, until
/// the link fails.
fn serve(link: &mut dyn Link, endpoint: &mut Endpoint) -> std::io::Result<()> {
    let start = Instant::now();
    let mut buf = [0u8; 2048];
    let mut out = Vec::with_capacity(2048);
    loop {
        let n = link.read(&mut buf)?;
        // Milliseconds since start, wrapping as the firmware's clock does (49.7 days a lap).
        let now_ms = start.elapsed().as_millis() as u32;
        let mut send = |frame: &[u8]| out.extend_from_slice(frame);
        for &byte in buf.get(..n).unwrap_or(&[]) {
            endpoint.receive(byte, now_ms, &mut send);
        }
        endpoint.poll(now_ms, &mut send);
        if !out.is_empty() {
            link.write(&out)?;
            out.clear();
        }
    }
}

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    let run = || -> Result<(), String> {
        let mut endpoint = endpoint(&args)?;
        if args.check {
            print!("{}", params::listing(endpoint.params()));
            return Ok(());
        }
        let (mut link, name) = open(&args)?;
        let params = endpoint.params();
        println!(
            "twocars-companion {}: MAVLink endpoint on {name}, system {} component 191, signing {}",
            env!("CARGO_PKG_VERSION"),
            params.byte(index::SYSID),
            if endpoint.signing() { "on" } else { "off" }
        );
        serve(link.as_mut(), &mut endpoint).map_err(|e| format!("{name}: {e}"))
    };
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("twocars-companion: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
