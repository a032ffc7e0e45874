//! The value tables the `qemu-tables` image carries, read on the host from the files it was
//! built with, and picked for a game's ratios as its Configure picks them.

use twocars::value_tables::ValueTables;

use crate::image::Image;

/// The sets the image carries, read from the files it was built with.
pub fn image_sets() -> Result<&'static [ValueTables<'static>], String> {
    let mut sets = Vec::new();
    for path in crate::image::tables::solve::flash_sets(Image::QemuTables.table_sets())? {
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        sets.push(ValueTables::parse(bytes).map_err(|e| format!("{}: {e:?}", path.display()))?);
    }
    Ok(Box::leak(sets.into_boxed_slice()))
}

/// The set of the `qemu-tables` image that fits the ratios of `limits`, as the firmware's
/// Configure picks it (the first that fits).
pub fn table_set(
    limits: [f64; 4],
    variant: twocars::Variant,
    dt: f64,
) -> Result<&'static ValueTables<'static>, String> {
    let sets = image_sets()?;
    let [v_pm, w_pm, v_em, w_em] = limits.map(|v| v as f32);
    let law = twocars::Law::new(
        twocars::Limits::<f32>::new(v_pm, w_pm, v_em, w_em).map_err(|e| e.to_string())?,
        variant,
    );
    let guidance = twocars::Guidance::new(law, dt as f32, twocars::Policy::Paper)
        .map_err(|_| "invalid --dt".to_string())?;
    let carried: Vec<String> = crate::image::tables::sets::FLASH_SETS
        .iter()
        .map(|set| format!("{:?}", set.limits))
        .collect();
    sets.iter()
        .find(|set| guidance.clone().set_tables(set).is_ok())
        .ok_or_else(|| {
            format!(
                "the qemu-tables image has no value tables for the ratios of {limits:?} (it carries those of {}); --policy flight plays without them",
                carried.join(" and ")
            )
        })
}
