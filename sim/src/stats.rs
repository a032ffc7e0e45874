//! Quantiles of sorted samples, as every report and test of the project states them.

/// The `q`-quantile (0 to 1) of `sorted` (ascending): the sample at rank (n - 1) q rounded to
/// the nearest; `None` for no samples.
pub fn quantile<T: Copy>(sorted: &[T], q: f64) -> Option<T> {
    let last = sorted.len().checked_sub(1)?;
    let rank = (last as f64 * q.clamp(0.0, 1.0)).round() as usize;
    sorted.get(rank).copied()
}

/// [`quantile`] of `f64` samples, NaN for none.
pub fn quantile_f64(sorted: &[f64], q: f64) -> f64 {
    quantile(sorted, q).unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_round_to_the_nearest_and_no_samples_have_none() {
        let v = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(quantile_f64(&v, 0.0), 1.0);
        assert_eq!(quantile_f64(&v, 0.5), 3.0);
        assert_eq!(quantile_f64(&v, 0.9), 4.0);
        assert_eq!(quantile_f64(&v, 0.3), 2.0);
        assert!(quantile_f64(&[], 0.5).is_nan());
        assert_eq!(quantile::<u64>(&[], 1.0), None);
    }
}
