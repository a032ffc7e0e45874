//! A UART in simulated time, after the STM32F4 USART: a one-byte receive data register with
//! RXNE and the overrun, framing and noise flags (read SR then DR to clear them), a transmit
//! holding register in front of a shift register, each byte taking ten bit times on the line,
//! and a level interrupt while RXNE (or a fault) is set, or while TXE is set and enabled.
//!
//! It drives the firmware's own code: the shared interrupt handler
//! ([`twocars::serial::InterruptEnd::on_interrupt`]) runs at each event that raises the
//! interrupt, and the loop ([`twocars::serial::service`]) between them, each pass charged its
//! CPU time. [`run_polled`] runs the loop the boards had before, which polled the data register
//! and reset on a line fault, over the same model.

use std::cell::RefCell;
use std::collections::VecDeque;

use twocars::protocol::endpoint::Endpoint;
use twocars::serial::{service, Board, Line, RxFlags, UartRegisters};

/// A byte the peer puts on the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineByte {
    /// When its stop bit ends, ns.
    pub at_ns: u64,
    /// The byte.
    pub byte: u8,
    /// Received without its stop bit (a framing error injected on the line).
    pub framing_error: bool,
}

/// The CPU's costs, from `cargo xtask bench` on the Cortex-M4F at 168 MHz.
#[derive(Clone, Copy, Debug)]
pub struct Cpu {
    /// Core clock, Hz.
    pub hz: u64,
    /// Cycles per received byte in the loop (deframing, CRC).
    pub cycles_per_byte: u64,
    /// Cycles per reply (the law for a State, encoding, queueing).
    pub cycles_per_reply: u64,
}

/// The STM32F405 at 168 MHz: a State frame costs about 3,000 instructions (the bench's serial
/// loop), counted here as cycles.
pub const STM32F405: Cpu = Cpu {
    hz: 168_000_000,
    cycles_per_byte: 30,
    cycles_per_reply: 3_000,
};

impl Cpu {
    fn ns(&self, cycles: u64) -> u64 {
        cycles * 1_000_000_000 / self.hz
    }
}

/// The UART and the time.
#[derive(Debug)]
pub struct UartModel {
    /// Nanoseconds per byte on the line (ten bits: start, eight data, stop).
    byte_ns: u64,
    now_ns: u64,
    incoming: VecDeque<LineByte>,
    rx_data: Option<u8>,
    flags: RxFlags,
    tx_holding: Option<u8>,
    /// The byte being shifted out and when its stop bit ends.
    tx_shifting: Option<(u64, u8)>,
    tx_interrupt_enabled: bool,
    /// Bytes the unit put on the line, with the time each one's stop bit ended.
    pub sent: Vec<(u64, u8)>,
}

impl UartModel {
    /// A UART at `baud` about to receive `incoming` (in time order).
    pub fn new(baud: u64, incoming: Vec<LineByte>) -> Self {
        UartModel {
            byte_ns: 10 * 1_000_000_000 / baud,
            now_ns: 0,
            incoming: incoming.into(),
            rx_data: None,
            flags: RxFlags::default(),
            tx_holding: None,
            tx_shifting: None,
            tx_interrupt_enabled: false,
            sent: Vec::new(),
        }
    }

    /// Simulated time, ns.
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    fn interrupt_pending(&self) -> bool {
        let received = self.rx_data.is_some() || self.flags != RxFlags::default();
        received || (self.tx_interrupt_enabled && self.tx_holding.is_none())
    }

    fn next_event(&self) -> Option<u64> {
        let arrival = self.incoming.front().map(|b| b.at_ns);
        let sent = self.tx_shifting.map(|(t, _)| t);
        arrival.into_iter().chain(sent).min()
    }

    /// Whether the peer has nothing left to send and the transmitter is idle.
    pub fn quiet(&self) -> bool {
        self.incoming.is_empty() && self.tx_shifting.is_none() && self.tx_holding.is_none()
    }

    fn start_shifting(&mut self) {
        if self.tx_shifting.is_none() {
            if let Some(byte) = self.tx_holding.take() {
                self.tx_shifting = Some((self.now_ns + self.byte_ns, byte));
            }
        }
    }

    /// One event at its time: a byte received (an overrun if RXNE is still set: the new byte
    /// is lost) or a byte sent.
    fn fire(&mut self, at: u64) {
        self.now_ns = at;
        if self.tx_shifting.is_some_and(|(t, _)| t == at) {
            if let Some((t, byte)) = self.tx_shifting.take() {
                self.sent.push((t, byte));
            }
            self.start_shifting();
        }
        if self.incoming.front().is_some_and(|b| b.at_ns == at) {
            let Some(b) = self.incoming.pop_front() else {
                return;
            };
            if self.rx_data.is_some() {
                self.flags.overrun = true;
            } else {
                self.rx_data = Some(b.byte);
                self.flags.framing |= b.framing_error;
            }
        }
    }

    /// Advances to `until_ns`, running `handler` whenever the interrupt is raised (the handler
    /// takes no time); `None`: interrupts off (the polled loop).
    fn advance(&mut self, until_ns: u64, mut handler: Option<&mut dyn FnMut(&mut UartModel)>) {
        loop {
            if let Some(h) = handler.as_mut() {
                // The handler clears what raised it; a bound guards the model, not the code.
                for _ in 0..4 {
                    if !self.interrupt_pending() {
                        break;
                    }
                    h(self);
                }
            }
            match self.next_event() {
                Some(t) if t <= until_ns => self.fire(t),
                _ => break,
            }
        }
        self.now_ns = self.now_ns.max(until_ns);
    }
}

impl UartRegisters for UartModel {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        let flags = std::mem::take(&mut self.flags);
        let byte = self.rx_data.take();
        (byte.is_some() || flags != RxFlags::default()).then_some((byte, flags))
    }
    fn can_transmit(&self) -> bool {
        self.tx_holding.is_none()
    }
    fn transmit(&mut self, byte: u8) {
        self.tx_holding = Some(byte);
        self.start_shifting();
    }
    fn transmit_idle(&mut self) {
        self.tx_interrupt_enabled = false;
    }
}

/// The loop's board over the model: its clock, and TXEIE set by `start_transmit`.
struct ModelBoard<'a>(&'a RefCell<UartModel>);

impl Board for ModelBoard<'_> {
    fn now_ms(&self) -> u32 {
        (self.0.borrow().now_ns / 1_000_000) as u32
    }
    fn start_transmit(&self) {
        self.0.borrow_mut().tx_interrupt_enabled = true;
    }
}

/// What a run left: the bytes the unit sent (with times), its counters.
#[derive(Debug)]
pub struct Served {
    /// Bytes on the line from the unit.
    pub sent: Vec<(u64, u8)>,
    /// The unit's counters at the end (line faults included where the loop records them).
    pub counters: twocars::protocol::message::Counters,
    /// Times the unit reset (the polled loop resets on a line fault).
    pub resets: u32,
}

/// Runs the interrupt-driven serial path (shared handler, queues, loop) over `uart` until the
/// peer is done and every reply is out.
pub fn run_interrupt_driven(uart: UartModel, cpu: Cpu) -> Served {
    let uart = RefCell::new(uart);
    let mut line = Line::new();
    let (mut interrupt, mut main) = line.split();
    let mut unit = Endpoint::<f32>::new();
    let board = ModelBoard(&uart);
    loop {
        let pass = service(&mut main, &board, &mut unit);
        let mut u = uart.borrow_mut();
        let busy = cpu.ns(pass.bytes as u64 * cpu.cycles_per_byte)
            + cpu.ns(pass.replies as u64 * cpu.cycles_per_reply);
        let until = if busy > 0 {
            u.now_ns + busy
        } else if main.nothing_received() && main.all_sent() && u.quiet() {
            break;
        } else {
            // Asleep until the next byte (or the next millisecond tick).
            u.next_event()
                .unwrap_or(u.now_ns)
                .min((u.now_ns / 1_000_000 + 1) * 1_000_000)
        };
        u.advance(
            until,
            Some(&mut |m: &mut UartModel| interrupt.on_interrupt(m)),
        );
    }
    let served = Served {
        sent: std::mem::take(&mut uart.borrow_mut().sent),
        counters: *unit.counters(),
        resets: 0,
    };
    served
}

/// Runs the loop the boards ran before the interrupt-driven path: poll the data register, feed
/// the unit, write each reply byte by byte as the transmitter takes it (receiving nothing
/// meanwhile), and on a line fault reset (the unit restarts unconfigured), over `uart`.
pub fn run_polled(uart: UartModel, cpu: Cpu) -> Served {
    let mut uart = uart;
    let mut unit = Endpoint::<f32>::new();
    let mut resets = 0;
    loop {
        let now_ms = (uart.now_ns / 1_000_000) as u32;
        if let Some(reply) = unit.poll(now_ms).map(|r| r.as_bytes().to_vec()) {
            write_polled(&mut uart, &reply, cpu);
        }
        // The HAL's read: SR, then DR; any fault flag is an error (and the byte is discarded).
        let byte = match uart.take_received() {
            Some((byte, flags)) if flags == RxFlags::default() => byte,
            Some(_) => {
                resets += 1;
                unit = Endpoint::<f32>::new();
                None
            }
            None => None,
        };
        let Some(byte) = byte else {
            if uart.quiet() {
                break;
            }
            let next = uart.next_event().unwrap_or(uart.now_ns);
            uart.advance(next, None);
            continue;
        };
        let t = uart.now_ns + cpu.ns(cpu.cycles_per_byte);
        uart.advance(t, None);
        if let Some(reply) = unit.receive(byte, now_ms).map(|r| r.as_bytes().to_vec()) {
            write_polled(&mut uart, &reply, cpu);
        }
    }
    Served {
        sent: uart.sent,
        counters: *unit.counters(),
        resets,
    }
}

/// The polled loop's reply: its CPU time, then each byte written as soon as the holding
/// register is empty, nothing received meanwhile.
fn write_polled(uart: &mut UartModel, reply: &[u8], cpu: Cpu) {
    let t = uart.now_ns + cpu.ns(cpu.cycles_per_reply);
    uart.advance(t, None);
    for &b in reply {
        while !uart.can_transmit() {
            let next = uart.next_event().unwrap_or(uart.now_ns);
            uart.advance(next, None);
        }
        uart.transmit(b);
    }
}
