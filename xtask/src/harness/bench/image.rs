//! The bench images: the CPUs they run on, building them, running them in QEMU with
//! `-icount` and reading what they print.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use twocars_bench::STATES;

/// One emulated CPU the bench runs on.
#[derive(Clone, Copy)]
pub struct Cpu {
    pub(crate) name: &'static str,
    pub(crate) target: &'static str,
    pub(crate) machine: &'static [&'static str],
    /// SysTick ticks per instruction under `-icount shift=6` (64 ns per instruction).
    pub(crate) ticks_per_instruction: f64,
}

impl Cpu {
    /// Its name in the tables.
    pub fn name(&self) -> &'static str {
        self.name
    }
    /// QEMU on this CPU's machine, headless, semihosting to the host, loading `elf`; the caller
    /// adds its own options (instruction counting, execution log).
    pub fn qemu(&self, elf: &std::path::Path) -> Result<Command, String> {
        let mut command = Command::new(crate::util::setup::qemu_binary()?);
        command
            .args(self.machine)
            .args(["-display", "none", "-monitor", "none", "-serial", "none"])
            .args(["-semihosting-config", "enable=on,target=native"])
            .arg("-kernel")
            .arg(elf);
        Ok(command)
    }
}

pub const M4F: Cpu = Cpu {
    name: "Cortex-M4F (mps2-an386)",
    target: "thumbv7em-none-eabihf",
    machine: &["-M", "mps2-an386", "-cpu", "cortex-m4"],
    // SysTick on the 25 MHz processor clock: 64 ns x 25 MHz.
    ticks_per_instruction: 1.6,
};

pub const M0: Cpu = Cpu {
    name: "Cortex-M0 (micro:bit)",
    target: "thumbv6m-none-eabi",
    machine: &["-M", "microbit"],
    // SysTick on the 16 MHz processor clock: 64 ns x 16 MHz.
    ticks_per_instruction: 1.024,
};

/// Per-state figures of one image.
pub struct Measured {
    /// SysTick ticks of each evaluation.
    pub ticks: Vec<f64>,
    /// Stack high-water mark of each evaluation, bytes.
    pub stack: Vec<u64>,
    /// Upper value (s) and the commands w_p, w_e (1/m) of each state, as the image computed them.
    pub outputs: Vec<[f32; 3]>,
    /// Flash of the image, bytes.
    pub flash: u64,
}

/// Builds the law's bench image `bin` for `cpu`, runs it in QEMU with `-icount` and reads its
/// per-state lines.
pub fn build_and_run(cpu: Cpu, bin: &str) -> Result<Measured, String> {
    let (out, flash) = build_and_print(cpu, bin)?;
    let mut m = Measured {
        ticks: Vec::new(),
        stack: Vec::new(),
        outputs: Vec::new(),
        flash,
    };
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if let ["state", _, ticks, stack, values @ ..] = fields.as_slice() {
            let bad = || format!("bad line {line}");
            m.ticks.push(ticks.parse().map_err(|_| bad())?);
            m.stack.push(stack.parse().map_err(|_| bad())?);
            let mut output = [0.0f32; 3];
            for (o, v) in output.iter_mut().zip(values) {
                *o = f32::from_bits(u32::from_str_radix(v, 16).map_err(|_| bad())?);
            }
            m.outputs.push(output);
        }
    }
    if m.ticks.len() != STATES.len() {
        return Err(format!(
            "bench on {}: {} of {} states reported",
            cpu.name,
            m.ticks.len(),
            STATES.len()
        ));
    }
    Ok(m)
}

/// Builds the bench image `bin` for `cpu` and runs it in QEMU with `-icount`: what it printed,
/// and its flash.
pub(crate) fn build_and_print(cpu: Cpu, bin: &str) -> Result<(String, u64), String> {
    build_and_print_with(cpu, bin, &[])
}

/// [`build_and_print`] with environment variables for the build (`TWOCARS_MAVLINK_CAPTURE`).
pub(crate) fn build_and_print_with(
    cpu: Cpu,
    bin: &str,
    env: &[(&str, &std::ffi::OsStr)],
) -> Result<(String, u64), String> {
    let elf = build_with(cpu, bin, env)?;
    let flash = crate::image::size::of(&elf)?.flash();
    let mut child = cpu
        .qemu(&elf)?
        .args(["-icount", "shift=6"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("bench on {} timed out", cpu.name));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut out = String::new();
    if let Some(mut stdout) = child.stdout.take() {
        std::io::Read::read_to_string(&mut stdout, &mut out).map_err(|e| e.to_string())?;
    }
    if !status.success() {
        return Err(format!("bench on {} exited with {status}", cpu.name));
    }
    Ok((out, flash))
}

/// The bench images (`bench/src/bin/`) and the features of `twocars-bench` each needs.
const IMAGES: [(&str, &str); 18] = [
    ("law", "qemu"),
    ("empty", "qemu"),
    ("law_fixed", "qemu"),
    ("empty_fixed", "qemu"),
    ("law_micromath", "qemu,micromath"),
    ("empty_micromath", "qemu,micromath"),
    ("law_report", "qemu"),
    ("empty_report", "qemu"),
    ("serial", "qemu,serial"),
    ("serial_fixed", "qemu,serial"),
    ("serial_tables", "qemu,serial,tables"),
    ("mavlink", "qemu,mavlink"),
    ("replay", "qemu,mavlink"),
    ("table", "qemu,tables"),
    ("estimate", "qemu"),
    ("estimate_fixed", "qemu"),
    ("team", "qemu"),
    ("team_fixed", "qemu"),
];

/// Builds the bench image `bin` for `cpu`, with only the features it needs (so that the core
/// carries no code the image does not use); returns the ELF's path.
pub fn build(cpu: Cpu, bin: &str) -> Result<PathBuf, String> {
    build_with(cpu, bin, &[])
}

fn build_with(cpu: Cpu, bin: &str, env: &[(&str, &std::ffi::OsStr)]) -> Result<PathBuf, String> {
    let features = IMAGES
        .iter()
        .find(|(name, _)| *name == bin)
        .map(|(_, features)| *features)
        .ok_or_else(|| format!("no bench image {bin}"))?;
    crate::image::build_image(
        "twocars-bench",
        cpu.target,
        features,
        bin,
        Stdio::null(),
        env,
    )
    .map_err(|e| format!("bench build of {bin} for {} failed: {e}", cpu.name))
}
