//! STM32F405 flight controller: USART1 (PA9 TX, PA10 RX, 115200 8N1) and a SysTick millisecond
//! clock at 168 MHz from an 8 MHz crystal.
//!
//! The HAL implements `embedded_io::Write` but reads through `embedded-hal-nb`; [`Port`] adds
//! `Read` and `ReadReady` with a one-byte look-ahead so the shared loop serves this board too.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use embedded_hal_nb::nb;
use embedded_hal_nb::serial::Read as _;
use stm32f4xx_hal::pac::USART1;
use stm32f4xx_hal::serial::{Error, Serial};

use crate::firmware::Clock;

/// USART1 with a one-byte look-ahead.
pub struct Port {
    serial: Serial<USART1>,
    pending: Option<u8>,
}

impl Port {
    /// Wraps a configured USART1.
    pub fn new(serial: Serial<USART1>) -> Self {
        Port {
            serial,
            pending: None,
        }
    }

    fn poll(&mut self) -> Result<(), Error> {
        if self.pending.is_none() {
            match self.serial.read() {
                Ok(byte) => self.pending = Some(byte),
                Err(nb::Error::WouldBlock) => {}
                Err(nb::Error::Other(e)) => return Err(e),
            }
        }
        Ok(())
    }
}

impl embedded_io::ErrorType for Port {
    type Error = Error;
}

impl embedded_io::ReadReady for Port {
    fn read_ready(&mut self) -> Result<bool, Error> {
        self.poll()?;
        Ok(self.pending.is_some())
    }
}

impl embedded_io::Read for Port {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Error> {
        let Some(first) = buf.first_mut() else {
            return Ok(0);
        };
        loop {
            self.poll()?;
            if let Some(byte) = self.pending.take() {
                *first = byte;
                return Ok(1);
            }
        }
    }
}

impl embedded_io::Write for Port {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Error> {
        embedded_io::Write::write(&mut self.serial, buf)
    }
    fn flush(&mut self) -> Result<(), Error> {
        embedded_io::Write::flush(&mut self.serial)
    }
}

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// SysTick at 1 kHz on the core clock.
pub struct SysTickClock {
    _syst: SYST,
}

impl SysTickClock {
    /// Starts SysTick with a 1 ms period for a core clock of `core_hz`.
    pub fn start(mut syst: SYST, core_hz: u32) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(core_hz / 1000 - 1);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        SysTickClock { _syst: syst }
    }
}

impl Clock for SysTickClock {
    fn now_ms(&self) -> u32 {
        MILLIS.load(Ordering::Relaxed)
    }
}

#[cortex_m_rt::exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}
