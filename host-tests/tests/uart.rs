//! The serial path over a UART model (`twocars_sim::uart_model`): a peer streams States at
//! 100 Hz without waiting for replies, a ReadCounters right behind every fifth, and framing
//! errors injected into some State frames. The interrupt-driven path answers every State but
//! those the faults hit; the polled loop the boards ran before loses more (it resets on a fault
//! and reads nothing while it writes a reply).

use std::collections::{BTreeSet, VecDeque};

use twocars::protocol::endpoint::Endpoint;
use twocars::serial::{service, Board, Line, RxFlags, UartRegisters};
use twocars_sim::link::{self, Reply, ReplyDecoder};
use twocars_sim::session::{paper_configure, paper_state};
use twocars_sim::uart_model::{run_interrupt_driven, run_polled, LineByte, UartModel, STM32F405};

/// States sent, over 2 s.
const STATES: u16 = 200;
/// First State's sequence number.
const FIRST: u16 = 100;

/// The peer's bytes on the line at `baud`, the sequence numbers of the States a framing error
/// hits inside the frame, and the number of faults in all (one hits a delimiter: replaced by a
/// delimiter, it costs nothing).
fn peer(baud: u64) -> (Vec<LineByte>, BTreeSet<u16>, usize) {
    let byte_ns = 10 * 1_000_000_000 / baud;
    let mut line = Vec::new();
    let mut hit = BTreeSet::new();
    let mut faults = 0;
    let put = |line: &mut Vec<LineByte>, start_ns: u64, bytes: &[u8], fault_at: Option<usize>| {
        let mut t = start_ns.max(line.last().map_or(0, |b: &LineByte| b.at_ns));
        for (i, &byte) in bytes.iter().enumerate() {
            t += byte_ns;
            line.push(LineByte {
                at_ns: t,
                byte,
                framing_error: fault_at == Some(i),
            });
        }
    };
    put(&mut line, 0, &link::configure(1, &paper_configure()), None);
    for k in 0..STATES {
        let sequence = FIRST + k;
        let t_ms = 20 + 10 * u32::from(k);
        let frame = link::state(sequence, &paper_state(usize::from(k), t_ms));
        // Every 23rd State: a framing error on one byte, at a different place each time; the
        // first on its delimiter.
        let fault_at = (k % 23 == 11).then(|| match k {
            11 => frame.len() - 1,
            _ => usize::from(k) % frame.len(),
        });
        if let Some(at) = fault_at {
            faults += 1;
            if at + 1 < frame.len() {
                hit.insert(sequence);
            }
        }
        put(&mut line, u64::from(t_ms) * 1_000_000, &frame, fault_at);
        if k % 5 == 4 {
            put(&mut line, 0, &link::read_counters(5000 + k), None);
        }
    }
    (line, hit, faults)
}

/// Replies decoded from the unit's bytes: the States answered with a Command (in order of
/// arrival), the Counters received, the frames that failed to decode.
fn answered(sent: &[(u64, u8)]) -> (Vec<u16>, usize, usize) {
    let bytes: Vec<u8> = sent.iter().map(|&(_, b)| b).collect();
    let mut states = Vec::new();
    let (mut counters, mut bad) = (0, 0);
    for reply in ReplyDecoder::default().feed(&bytes) {
        match reply {
            Ok(Reply::Command(s, _)) if (FIRST..FIRST + STATES).contains(&s) => states.push(s),
            Ok(Reply::Counters(..)) => counters += 1,
            Ok(_) => {}
            Err(_) => bad += 1,
        }
    }
    (states, counters, bad)
}

fn check_at(baud: u64) {
    let (line, hit, faults) = peer(baud);
    let all: BTreeSet<u16> = (FIRST..FIRST + STATES).collect();

    let served = run_interrupt_driven(UartModel::new(baud, line.clone()), STM32F405);
    let (states, counters, bad) = answered(&served.sent);
    let lost: BTreeSet<u16> = all
        .difference(&states.iter().copied().collect())
        .copied()
        .collect();
    let line_faults = served.counters.line;
    println!(
        "{baud} baud, interrupt-driven: {} States sent, {} answered, {} lost ({} hit by a framing \
         error inside the frame, of {faults} errors), {counters} Counters of {}, {bad} reply frames undecodable; line faults {line_faults:?}",
        STATES,
        states.len(),
        lost.len(),
        hit.len(),
        STATES / 5
    );
    assert_eq!(
        lost, hit,
        "interrupt-driven: lost exactly the States the faults hit"
    );
    assert!(states.windows(2).all(|w| w[0] < w[1]), "answered in order");
    assert_eq!(
        counters,
        usize::from(STATES / 5),
        "every ReadCounters answered"
    );
    assert_eq!(bad, 0, "every reply frame decodes");
    assert_eq!(line_faults.overrun, 0);
    assert_eq!(line_faults.tx_full + line_faults.rx_full, 0);
    // The unit's counters at the end count every framing error.
    assert_eq!(served.counters.line.framing as usize, faults);

    let polled = run_polled(UartModel::new(baud, line), STM32F405);
    let (states, _, _) = answered(&polled.sent);
    println!(
        "{baud} baud, polled (before): {} answered, {} lost, {} resets",
        states.len(),
        usize::from(STATES) - states.len(),
        polled.resets
    );
    assert!(
        usize::from(STATES) - states.len() > hit.len(),
        "the polled loop loses more than the faulted frames"
    );
}

#[test]
fn interrupt_driven_serial_loses_only_the_frames_faults_hit_at_115200_baud() {
    check_at(115_200);
}

#[test]
fn interrupt_driven_serial_loses_only_the_frames_faults_hit_at_921600_baud() {
    check_at(921_600);
}

/// A UART with a receive FIFO of any depth and a transmitter that never waits.
#[derive(Default)]
struct FakeUart {
    rx: VecDeque<(Option<u8>, RxFlags)>,
    sent: Vec<u8>,
}

impl FakeUart {
    /// `bytes` arrive, the one at `fault.0` with the flags `fault.1`.
    fn arrive(&mut self, bytes: &[u8], fault: Option<(usize, RxFlags)>) {
        for (i, &b) in bytes.iter().enumerate() {
            let flags = fault
                .filter(|f| f.0 == i)
                .map_or(RxFlags::default(), |f| f.1);
            self.rx.push_back((Some(b), flags));
        }
    }
}

impl UartRegisters for FakeUart {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        self.rx.pop_front()
    }
    fn can_transmit(&self) -> bool {
        true
    }
    fn transmit(&mut self, byte: u8) {
        self.sent.push(byte);
    }
    fn transmit_idle(&mut self) {}
}

struct Still;

impl Board for Still {
    fn now_ms(&self) -> u32 {
        0
    }
    fn start_transmit(&self) {}
}

/// The handler's faults each end the frame they land in: a full receive queue (the loop
/// stalled), an overrun, a parity error; the next frame is answered, and Counters report them.
#[test]
fn every_line_fault_costs_only_the_frame_it_lands_in() {
    let state = |s| link::state(s, &paper_state(0, 0));
    let mut line = Line::new();
    let (mut interrupt, mut main) = line.split();
    let mut unit = Endpoint::<f32>::new();
    let mut uart = FakeUart::default();
    let replies = |uart: &mut FakeUart| {
        let bytes = std::mem::take(&mut uart.sent);
        let decoded: Vec<Reply> = ReplyDecoder::default()
            .feed(&bytes)
            .into_iter()
            .map(|r| r.expect("replies decode"))
            .collect();
        decoded
    };
    let commands = |replies: &[Reply]| -> Vec<u16> {
        replies
            .iter()
            .filter_map(|r| match r {
                Reply::Command(s, _) => Some(*s),
                _ => None,
            })
            .collect()
    };

    // Configure, then 20 States in one interrupt while the loop stalls, with a receive queue of
    // 511 bytes: the bytes beyond it are dropped and counted, the State the drop cuts is
    // refused, the States whole in the queue are answered.
    let configure = link::configure(1, &paper_configure());
    uart.arrive(&configure, None);
    for s in 10..30 {
        uart.arrive(&state(s), None);
    }
    let queued_whole = {
        let mut total = configure.len();
        (10..30)
            .take_while(|&s| {
                total += state(s).len();
                total <= 511
            })
            .count()
    };
    interrupt.on_interrupt(&mut uart);
    service(&mut main, &Still, &mut unit);
    interrupt.on_interrupt(&mut uart);
    let got = replies(&mut uart);
    let sent = configure.len() + (10..30).map(|s| state(s).len()).sum::<usize>();
    assert_eq!(main.faults().rx_full as usize, sent - 511);
    assert_eq!(main.faults().tx_full, 0);
    assert_eq!(
        commands(&got),
        (10..10 + queued_whole as u16).collect::<Vec<_>>()
    );

    // A State whose byte 5 follows an overrun, one whose byte 9 failed its parity, a clean
    // one, ReadCounters: the clean one is answered, and Counters report the faults.
    uart.arrive(
        &state(40),
        Some((
            5,
            RxFlags {
                overrun: true,
                ..RxFlags::default()
            },
        )),
    );
    uart.arrive(
        &state(41),
        Some((
            9,
            RxFlags {
                parity: true,
                ..RxFlags::default()
            },
        )),
    );
    uart.arrive(&state(42), None);
    uart.arrive(&link::read_counters(43), None);
    interrupt.on_interrupt(&mut uart);
    service(&mut main, &Still, &mut unit);
    interrupt.on_interrupt(&mut uart);
    let got = replies(&mut uart);
    assert_eq!(commands(&got), [42]);
    let faults = main.faults();
    assert_eq!((faults.overrun, faults.parity, faults.framing), (1, 1, 0));
    assert!(
        got.iter()
            .any(|r| matches!(r, Reply::Counters(43, c) if c.line == faults)),
        "{got:?}"
    );
}
