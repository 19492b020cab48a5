//! The build-peak measurement of `appel bench`, in a test binary of its own: the peak and the
//! resident size are the whole process's, so other tests allocating in parallel threads would
//! disturb it.

use appel_bench::rss::{current_bytes, peak_bytes, reset_peak};

#[test]
fn a_reset_peak_sees_a_later_allocation_and_not_an_earlier_one() {
    if current_bytes().is_none() {
        return; // not Linux
    }
    let big = vec![1u8; 64 << 20];
    std::hint::black_box(&big);
    drop(big);
    assert!(reset_peak());
    let after_reset = peak_bytes().unwrap();
    let now = current_bytes().unwrap();
    // The 64 MB touched before the reset no longer counts.
    assert!(after_reset < now + (32 << 20), "{after_reset} {now}");
    let again = vec![2u8; 48 << 20];
    std::hint::black_box(&again);
    assert!(peak_bytes().unwrap() >= after_reset + (40 << 20));
}
