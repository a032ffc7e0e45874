//! `size`-style figures of a firmware image: flash (vector table, code, read-only data, data's
//! initial values) and static RAM (data, bss).

use object::{Object, ObjectSection, SectionFlags, SectionKind};

/// Section sizes of one image, bytes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ImageSize {
    /// .vector_table + .text.
    pub text: u64,
    /// .rodata.
    pub rodata: u64,
    /// .data (in flash and RAM).
    pub data: u64,
    /// .bss and .uninit (RAM only).
    pub bss: u64,
    /// Address of the vector table: must be the board's flash origin.
    pub vector_table: u64,
    /// Entry point (reset handler, Thumb bit set).
    pub entry: u64,
    /// Address of the RP2040's second-stage bootloader (`.boot2`, counted in `text`), if any.
    pub boot2: Option<u64>,
}

impl ImageSize {
    /// Bytes of flash.
    pub fn flash(&self) -> u64 {
        self.text + self.rodata + self.data
    }
    /// Bytes of static RAM (the stack comes on top).
    pub fn ram(&self) -> u64 {
        self.data + self.bss
    }
}

/// Reads the section sizes of an ELF image.
pub fn of(path: &std::path::Path) -> Result<ImageSize, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let file = object::File::parse(&*bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut size = ImageSize {
        entry: file.entry(),
        ..ImageSize::default()
    };
    for section in file.sections() {
        let alloc = matches!(section.flags(), SectionFlags::Elf { sh_flags } if sh_flags & u64::from(object::elf::SHF_ALLOC) != 0);
        if !alloc {
            continue;
        }
        let name = section.name().unwrap_or("");
        let n = section.size();
        match section.kind() {
            _ if name.starts_with(".boot2") => {
                size.text += n;
                size.boot2 = Some(section.address());
            }
            _ if name.starts_with(".vector_table") => {
                size.text += n;
                size.vector_table = section.address();
            }
            SectionKind::UninitializedData | SectionKind::UninitializedTls => size.bss += n,
            _ if name.starts_with(".bss") || name.starts_with(".uninit") => size.bss += n,
            SectionKind::Data | SectionKind::Tls => size.data += n,
            SectionKind::ReadOnlyData | SectionKind::ReadOnlyString => size.rodata += n,
            SectionKind::Text => size.text += n,
            _ => {}
        }
    }
    Ok(size)
}
