//! The QEMU image's defmt log, decoded in xtask with `defmt-decoder`, the library `defmt-print`
//! is built on: a bare machine has nothing more to install or compile on its first run (the
//! `defmt-print` install took 3 min 12 s there, compiling its own copy of the decoder).

use std::io::Read;
use std::path::Path;
use std::thread::JoinHandle;

use defmt_decoder::log::format::{Formatter, FormatterConfig};
use defmt_decoder::{DecodeError, Table};

/// Decodes the frames `input` carries (the emulator's semihosting stdout) with the table of
/// the image `elf`, printing each log line as `defmt-print` does (level, message), on a thread
/// of its own that ends with the stream.
///
/// # Errors
/// The ELF unreadable, or without a defmt table.
pub fn spawn(elf: &Path, input: impl Read + Send + 'static) -> Result<JoinHandle<()>, String> {
    let bytes = std::fs::read(elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let has_table = Table::parse(&bytes).map_err(|e| format!("{}: {e}", elf.display()))?;
    if has_table.is_none() {
        return Err(format!("{}: no defmt table", elf.display()));
    }
    Ok(std::thread::spawn(move || decode(&bytes, input)))
}

/// The decoding loop of [`spawn`].
fn decode(elf: &[u8], mut input: impl Read) {
    let Ok(Some(table)) = Table::parse(elf) else {
        return;
    };
    let config = FormatterConfig {
        is_timestamp_available: table.has_timestamp(),
        ..FormatterConfig::default()
    };
    let formatter = Formatter::new(config);
    let mut stream = table.new_stream_decoder();
    let mut buf = [0u8; 1024];
    loop {
        let n = match input.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        stream.received(buf.get(..n).unwrap_or(&[]));
        loop {
            match stream.decode() {
                Ok(frame) => println!("{}", formatter.format_frame(frame, None, None, None)),
                Err(DecodeError::UnexpectedEof) => break,
                Err(DecodeError::Malformed) if table.encoding().can_recover() => {}
                Err(DecodeError::Malformed) => {
                    eprintln!("xtask: the image's defmt log is malformed; no more of it is shown");
                    return;
                }
            }
        }
    }
}
