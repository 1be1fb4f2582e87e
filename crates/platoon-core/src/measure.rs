//! Summaries of measurements, shared by the benchmarks.

/// Median of timings (total order, so a NaN cannot panic a bench). Empty input gives NaN.
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_takes_the_middle_and_survives_nan() {
        assert_eq!(super::median(vec![3.0, 1.0, 2.0]), 2.0);
        assert!(super::median(vec![]).is_nan());
        assert_eq!(super::median(vec![f64::NAN, 1.0, 2.0]), 2.0);
    }
}
