// Runs an RP2040 image in rp2040js with UART0 on a loopback TCP port, as QEMU's
// `-serial tcp:...,server=on,wait=on` does for the other boards: the core starts once one client
// connects; bytes from the client go to UART0's receive FIFO, bytes UART0 sends go back.
//
//   node rp2040js_harness.mjs RP2040JS_DIR ELF PORT
//
// RP2040JS_DIR holds node_modules/rp2040js (xtask installs it there with npm). The package has
// no boot ROM, so the harness does what the ROM and boot2 would leave done: the ELF's segments
// in flash, VTOR at the vector table after boot2 (0x1000_0100), SP and PC from that table.
//
// Bytes from the client reach UART0 one per character time of the line's baud rate (10 bits
// of 8N1), as on a wire: rp2040js's receive FIFO would drop what a burst puts past its 32
// entries.
//
// Time: rp2040js's clock advances by the cycles the core executes at 125 MHz. While the core
// sleeps in WFI the harness moves it on with the wall clock, so the image's watchdog sees the
// host's silences as they are. On exit (the client closes) it prints the core's cycle count.

import { readFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [dir, elfPath, port] = process.argv.slice(2);
const { Simulator } = await import(
  pathToFileURL(join(dir, 'node_modules/rp2040js/dist/esm/index.js')).href
);

const FLASH = 0x10000000;
const VECTORS = FLASH + 0x100;

/** Copies the ELF32 file's loadable segments to flash at their load (physical) addresses. */
function loadElf(mcu, elf) {
  if (elf.readUInt32BE(0) !== 0x7f454c46 || elf[4] !== 1 || elf[5] !== 1) {
    throw new Error(`${elfPath}: not a 32-bit little-endian ELF`);
  }
  const phoff = elf.readUInt32LE(28);
  const phentsize = elf.readUInt16LE(42);
  const phnum = elf.readUInt16LE(44);
  for (let i = 0; i < phnum; i++) {
    const h = phoff + i * phentsize;
    const [type, offset, paddr, filesz] = [0, 4, 12, 16].map((o) => elf.readUInt32LE(h + o));
    if (type !== 1 || filesz === 0) continue;
    if (paddr < FLASH || paddr + filesz > FLASH + mcu.flash.length) {
      throw new Error(`segment at 0x${paddr.toString(16)} is outside flash`);
    }
    mcu.flash.set(elf.subarray(offset, offset + filesz), paddr - FLASH);
  }
}

const sim = new Simulator();
const mcu = sim.rp2040;
const { core, clock } = mcu;
loadElf(mcu, readFileSync(elfPath));
core.VTOR = VECTORS;
core.SP = mcu.flashView.getUint32(VECTORS - FLASH, true);
core.PC = mcu.flashView.getUint32(VECTORS - FLASH + 4, true) & ~1;

const CYCLE_NANOS = 1e9 / 125e6;
let started = 0;
let stopped = false;

/** Executes for about 10 ms of wall time, then yields to the event loop (the socket's bytes). */
function run() {
  const until = performance.now() + 10;
  while (!stopped && performance.now() < until) {
    // A WFI entered with an interrupt already pending (masked by PRIMASK) returns at once on
    // the chip; rp2040js would wait for the next one.
    if (core.waiting && core.pendingInterrupts & core.enabledInterrupts) {
      core.waiting = false;
    }
    if (core.waiting) {
      const behind = (performance.now() - started) * 1e6 - clock.nanos;
      if (behind <= 0) break;
      const alarm = clock.nanosToNextAlarm;
      clock.tick(alarm > 0 ? Math.min(alarm, behind) : behind);
    } else {
      for (let i = 0; i < 1000 && !core.waiting; i++) {
        clock.tick(core.executeInstruction() * CYCLE_NANOS);
      }
    }
  }
  if (!stopped) setImmediate(run);
}

/** Bytes from the client not yet on the line, and the alarm that puts the next one there. */
const line = [];
const uart = mcu.uart[0];
const characterNanos = () => {
  const baud = uart.baudRate;
  return (10 * 1e9) / (Number.isFinite(baud) && baud > 0 ? baud : 115200);
};
const feeder = clock.createAlarm(() => {
  if (line.length > 0) uart.feedByte(line.shift());
  if (line.length > 0) feeder.schedule(characterNanos());
});

const server = createServer((socket) => {
  server.close();
  socket.setNoDelay(true);
  uart.onByte = (byte) => socket.write(Buffer.of(byte));
  socket.on('data', (data) => {
    const idle = line.length === 0;
    line.push(...data);
    if (idle) feeder.schedule(characterNanos());
  });
  socket.on('close', () => {
    stopped = true;
    process.stdout.write(`rp2040js: ${core.cycles} cycles\n`);
  });
  socket.on('error', () => {});
  started = performance.now();
  run();
});
server.listen(Number(port), '127.0.0.1');
