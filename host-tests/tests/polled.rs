//! The guidance unit over a HAL's serial port (`twocars::polled`), on an in-memory port: the
//! scripted session answered as the unit answers it directly, the watchdog, Shutdown, and a
//! port's errors handed back.

use std::collections::VecDeque;

use embedded_hal_nb::nb;
use embedded_hal_nb::serial::{ErrorKind, ErrorType, Read, Write};
use twocars::polled::{serve, serve_pass, MAX_PASS_BYTES};
use twocars::protocol::endpoint::{Endpoint, STATUS_STALE_INPUT};
use twocars::protocol::frame::WireError;
use twocars_sim::link::{self, Reply, ReplyDecoder};
use twocars_sim::session::{paper_configure, paper_state, script, Expect};

/// An in-memory port: bytes to read, bytes written, and a fault to raise on the next read.
#[derive(Default)]
struct Port {
    input: VecDeque<u8>,
    output: Vec<u8>,
    fault: Option<ErrorKind>,
}

impl ErrorType for Port {
    type Error = ErrorKind;
}

impl Read<u8> for Port {
    fn read(&mut self) -> nb::Result<u8, ErrorKind> {
        if let Some(e) = self.fault.take() {
            return Err(nb::Error::Other(e));
        }
        self.input.pop_front().ok_or(nb::Error::WouldBlock)
    }
}

impl Write<u8> for Port {
    fn write(&mut self, byte: u8) -> nb::Result<(), ErrorKind> {
        self.output.push(byte);
        Ok(())
    }
    fn flush(&mut self) -> nb::Result<(), ErrorKind> {
        Ok(())
    }
}

impl Port {
    /// The replies written since the last call.
    fn replies(&mut self) -> Vec<Reply> {
        let bytes = std::mem::take(&mut self.output);
        ReplyDecoder::default()
            .feed(&bytes)
            .into_iter()
            .map(|r| r.expect("a valid reply"))
            .collect()
    }
}

#[test]
fn the_scripted_session_is_answered_over_the_port_as_the_unit_answers_it() {
    let mut unit = Endpoint::<f32>::new();
    let mut port = Port::default();
    for step in script() {
        port.input.extend(&step.bytes);
        let pass = serve_pass(&mut port, &mut unit, 0).expect("no fault");
        assert_eq!(pass.bytes, step.bytes.len(), "{}", step.name);
        let replies = port.replies();
        assert_eq!(replies.len(), 1, "{}: {replies:?}", step.name);
        match (step.expect, replies[0]) {
            (Expect::Ack, Reply::ConfigureAck(seq, _)) => assert_eq!(seq, step.sequence),
            (Expect::Error(code, _), Reply::Error(_, e)) => {
                assert_eq!(WireError::from_code(e.code), Some(code), "{}", step.name);
            }
            (Expect::Command(status), Reply::Command(seq, c)) => {
                assert_eq!((seq, c.status), (step.sequence, status), "{}", step.name);
            }
            (Expect::Counters, Reply::Counters(_, c)) => {
                assert_eq!(c.accepted, twocars_sim::session::accepted())
            }
            (want, got) => panic!("{}: expected {want:?}, got {got:?}", step.name),
        }
    }
}

#[test]
fn a_silent_sender_gets_the_safe_command_once_the_watchdog_expires() {
    let mut unit = Endpoint::<f32>::new();
    let mut port = Port::default();
    port.input.extend(link::configure(1, &paper_configure()));
    port.input.extend(link::state(2, &paper_state(0, 0)));
    serve_pass(&mut port, &mut unit, 0).expect("no fault");
    assert!(matches!(
        port.replies()[..],
        [Reply::ConfigureAck(..), Reply::Command(..)]
    ));
    // The watchdog (paper_configure: 0.5 s) has not expired at 400 ms, and has at 600 ms.
    assert_eq!(serve_pass(&mut port, &mut unit, 400).unwrap().replies, 0);
    assert_eq!(serve_pass(&mut port, &mut unit, 600).unwrap().replies, 1);
    let replies = port.replies();
    let [Reply::Command(_, c)] = replies[..] else {
        panic!("{replies:?}")
    };
    assert_eq!(
        (c.status, c.pursuer_rate, c.evader_rate),
        (STATUS_STALE_INPUT, 0.0, 0.0)
    );
}

#[test]
fn serving_stops_at_shutdown_and_a_pass_reads_a_bounded_number_of_bytes() {
    let mut unit = Endpoint::<f32>::new();
    let mut port = Port::default();
    port.input.extend(link::shutdown(9));
    port.input.extend([0u8; 10]);
    let mut clock = 0;
    serve(&mut port, &mut unit, || {
        clock += 10;
        clock
    })
    .expect("no fault");
    assert!(matches!(port.replies()[..], [Reply::ShutdownAck(9)]));
    // What follows the Shutdown stays for whoever reads the port next.
    assert_eq!(port.input.len(), 10);

    let mut noisy = Port::default();
    noisy
        .input
        .extend(std::iter::repeat_n(0x55, 3 * MAX_PASS_BYTES));
    let pass = serve_pass(&mut noisy, &mut Endpoint::<f32>::new(), 0).expect("no fault");
    assert_eq!(pass.bytes, MAX_PASS_BYTES);
}

#[test]
fn a_port_fault_is_handed_back_and_the_unit_serves_on() {
    let mut unit = Endpoint::<f32>::new();
    let mut port = Port::default();
    port.input.extend(link::configure(1, &paper_configure()));
    port.fault = Some(ErrorKind::Overrun);
    assert_eq!(serve_pass(&mut port, &mut unit, 0), Err(ErrorKind::Overrun));
    // The bytes behind the fault are read on the next pass.
    let pass = serve_pass(&mut port, &mut unit, 0).expect("no fault");
    assert_eq!(pass.replies, 1);
    assert!(matches!(port.replies()[..], [Reply::ConfigureAck(1, _)]));
}
