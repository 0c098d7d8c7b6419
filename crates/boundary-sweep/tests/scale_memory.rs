//! The scale tier's peak memory with the counting allocator the sweep binary installs.

use boundary_sweep::scale::{run_scale, Family, MemoryProbe, ScaleOptions, ScaleScene};
use peakmem_alloc::{PeakMemAlloc, PeakMemAllocTrait, INSTRUMENTED_SYSTEM};
use std::alloc::System;

#[global_allocator]
static HEAP: &PeakMemAlloc<System> = &INSTRUMENTED_SYSTEM;

struct Probe;

impl MemoryProbe for Probe {
    fn reset(&self) {
        HEAP.reset_peak_memory();
    }
    fn peak_bytes(&self) -> Option<usize> {
        Some(HEAP.get_peak_memory())
    }
}

/// The peak covers at least the labels (one byte per particle) and grows with the set; per
/// particle it stays within what a neighbour grid and per-thread scratch can explain.
#[test]
fn peak_memory_holds_the_labels_and_grows_with_the_set() {
    let opts = ScaleOptions {
        scenes: vec![
            ScaleScene::new(Family::Ball, 4_000),
            ScaleScene::new(Family::Ball, 32_000),
        ],
        methods: vec!["exact".into(), "marrone".into()],
        runs: 1,
        budget: 1e9,
        threads: 1,
        thread_scan: None,
    };
    let out = run_scale(&opts, &Probe, &mut |_| {}).unwrap();
    assert_eq!(out.rows.len(), 4);
    for row in &out.rows {
        let peak = row.peak_bytes.unwrap();
        assert!(peak >= row.n, "{row:?}");
        let per = row.bytes_per_particle().unwrap();
        assert!(per < 20_000.0, "{row:?}");
    }
    for method in ["exact", "marrone"] {
        let peaks: Vec<usize> = out
            .rows
            .iter()
            .filter(|r| r.method == method)
            .map(|r| r.peak_bytes.unwrap())
            .collect();
        assert!(peaks[1] > 4 * peaks[0], "{method}: {peaks:?}");
    }
}
