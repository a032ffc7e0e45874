//! The value table's bench on the target: the table [`crate::TABLE`] read at each point of
//! [`crate::TABLE_POINTS`] (V and the pursuer's optimal turn) against the same call reading
//! nothing, one line per point: `table <i> <ticks> <empty ticks> <stack bytes> <value bits> <turn>`.

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::value_tables::ValueTables;

use super::probe;
use crate::{TABLE, TABLE_POINTS};

/// The bench's value table, [`crate::TABLE`], parsed once into a static; `None` if it does
/// not parse (or on a second call).
pub fn tables() -> Option<&'static ValueTables<'static>> {
    let table = ValueTables::parse(black_box(TABLE)).ok()?;
    cortex_m::singleton!(: ValueTables<'static> = table).map(|t| &*t)
}

/// Reads the table at every point, printing one `table` line each, and exits.
pub fn run() -> ! {
    probe::start();
    let Some(table) = tables() else {
        hprintln!("the bench table does not parse");
        probe::fail();
    };
    for (i, &point) in TABLE_POINTS.iter().enumerate() {
        let start = probe::now();
        let empty = read_nothing(black_box(table), black_box(point));
        let empty_ticks = probe::ticks_since(start);
        black_box(empty);
        let bottom = probe::paint();
        let start = probe::now();
        let (value, turn) = read_table(black_box(table), black_box(point));
        let ticks = probe::ticks_since(start);
        let stack = probe::used(bottom);
        hprintln!(
            "table {} {} {} {} {:08x} {}",
            i,
            ticks,
            empty_ticks,
            stack,
            value.to_bits(),
            turn
        );
    }
    probe::succeed()
}

/// The timed region: V and the pursuer's optimal turn at `point` (r_p, r_p, rad).
#[inline(never)]
fn read_table(table: &ValueTables<'_>, [x, y, phi]: [f32; 3]) -> (f32, f32) {
    (
        table.value(x, y, phi).unwrap_or(f32::INFINITY),
        table.pursuer_turn(x, y, phi).unwrap_or(f32::NAN),
    )
}

/// The same call reading nothing: its ticks are the call overhead.
#[inline(never)]
fn read_nothing(table: &ValueTables<'_>, point: [f32; 3]) -> (f32, f32) {
    black_box((table, point));
    (0.0, 0.0)
}
