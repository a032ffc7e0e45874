//! The value tables an image carries in flash (feature `tables-in-flash`): the sets
//! `build.rs` includes from the files `TWOCARS_VALUE_TABLES` names, one per pair of ratios,
//! each parsed once at start-up (docs/near-field.md).

use heapless::Vec;

use crate::value_tables::ValueTables;

// `SETS: [&[u8]; SET_COUNT]`, written by build.rs.
include!(concat!(env!("OUT_DIR"), "/value_table_sets.rs"));

/// The image's sets, parsed once into a static and lent for the program's life (for
/// [`crate::protocol::endpoint::Endpoint::set_tables`]); a set that does not parse is left
/// out, so the unit serves without it (its Configure then says policy 1). `None` on a second
/// call.
pub fn take_value_tables() -> Option<&'static [ValueTables<'static>]> {
    let mut sets: Vec<ValueTables<'static>, SET_COUNT> = Vec::new();
    for bytes in SETS {
        if let Ok(set) = ValueTables::parse(bytes) {
            // Never full: one place per set (`push` rather than `collect`, which may panic).
            let _ = sets.push(set);
        }
    }
    let sets = cortex_m::singleton!(: Vec<ValueTables<'static>, SET_COUNT> = sets)?;
    Some(sets.as_slice())
}
