//! The value table's row of `cargo xtask bench`: the firmware's reader of a
//! Hamilton-Jacobi-Isaacs table (`twocars::value_tables::table`) on the Cortex-M4F (`table`
//! image, the table `bench/table.tcv`), checked against the same reads on the host.

use twocars::value_tables::table::ValueTable;
use twocars::value_tables::ValueTables;
use twocars_bench::TABLE_POINTS;

use crate::harness::bench::image::{build_and_print, M4F};

/// The table the bench image carries.
const TABLE: &[u8] = twocars_bench::TABLE;

/// What reading the table costs on the Cortex-M4F.
#[derive(Clone, Copy, Debug)]
pub struct TableMeasured {
    /// Instructions per read (V and the pursuer's optimal turn), mean, min, max.
    pub mean: f64,
    /// The cheapest read.
    pub min: f64,
    /// The dearest read.
    pub max: f64,
    /// Stack of a read, bytes.
    pub stack: u64,
}

/// Runs the table bench on the Cortex-M4F; an error where a read differs from the host's.
pub fn measure() -> Result<TableMeasured, String> {
    let table = ValueTables::parse(TABLE).map_err(|e| format!("bench/table.tcv: {e:?}"))?;
    let (out, _) = build_and_print(M4F, "table")?;
    let mut instructions = Vec::new();
    let mut stack = 0;
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let ["table", i, t, e, s, v, turn] = fields.as_slice() else {
            continue;
        };
        let bad = || format!("bad line {line}");
        let i: usize = i.parse().map_err(|_| bad())?;
        let [x, y, phi] = *TABLE_POINTS.get(i).ok_or_else(bad)?;
        let want = (
            table.value(x, y, phi).unwrap_or(f32::INFINITY).to_bits(),
            table.pursuer_turn(x, y, phi).unwrap_or(f32::NAN),
        );
        let got = (
            u32::from_str_radix(v, 16).map_err(|_| bad())?,
            turn.parse::<f32>().map_err(|_| bad())?,
        );
        if got.0 != want.0 || got.1.to_bits() != want.1.to_bits() {
            return Err(format!(
                "table point {i}: Cortex-M4F {got:?}, host {want:?}"
            ));
        }
        let ticks = t.parse::<f64>().map_err(|_| bad())? - e.parse::<f64>().map_err(|_| bad())?;
        instructions.push(ticks / M4F.ticks_per_instruction);
        stack = stack.max(s.parse().map_err(|_| bad())?);
    }
    if instructions.len() != TABLE_POINTS.len() {
        return Err(format!(
            "the table bench reported {} of {} points:\n{out}",
            instructions.len(),
            TABLE_POINTS.len()
        ));
    }
    Ok(TableMeasured {
        mean: instructions.iter().sum::<f64>() / instructions.len() as f64,
        min: instructions.iter().copied().fold(f64::INFINITY, f64::min),
        max: instructions.iter().copied().fold(0.0, f64::max),
        stack,
    })
}

/// The bench page's paragraph.
pub fn paragraph(m: &TableMeasured) -> String {
    let (n, headings) = ValueTable::parse(TABLE).map_or((0, 0), |t| t.grid());
    format!(
        "Value table (Cortex-M4F, f32; `table` image: `twocars::value_tables::table` \
         reading `bench/table.tcv`, the paper's game on a {n} x {n} x {headings} grid, \
         {} B, u16 per node; each read is V by trilinear interpolation and the pursuer's \
         optimal turn by the solver's one-step minimax, twelve exact steps and twelve more \
         interpolations; at the {} points of \
         `twocars_bench::TABLE_POINTS`, every result equal to the host's bit for bit): \
         **{:.0} instructions per read** ({:.0} - {:.0}; the call overhead, the same call \
         reading nothing, subtracted); stack {} B. A read costs the same on any grid size.\n",
        TABLE.len(),
        TABLE_POINTS.len(),
        m.mean,
        m.min,
        m.max,
        m.stack
    )
}
