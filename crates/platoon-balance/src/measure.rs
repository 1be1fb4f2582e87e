//! Summaries of measurements, shared by the benchmarks.

use std::time::Duration;

/// A render's device time: the GPU's timestamps where the device has them, else the wall
/// time (lavapipe reports none).
pub fn device_time(gpu: Duration, wall: Duration) -> Duration {
    if gpu.is_zero() {
        wall
    } else {
        gpu
    }
}

/// Median of timings (total order, so a NaN cannot panic a bench). Empty input gives NaN.
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The value at share `p` (0..=1) of the sorted timings, nearest rank. Empty input gives NaN.
pub fn percentile(mut v: Vec<f64>, p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
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
