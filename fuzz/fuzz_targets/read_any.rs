//! Arbitrary bytes through every reader (CSV, XYZ, PLY, VTK) with every dimension option:
//! `Ok` or `Err`, never a panic or an allocation sized by an unchecked header count; an error is
//! one line naming the source; a set read with `dim` given has that dimension.
#![no_main]

use boundary_io::{read_particles_from, Format, ReadOptions};
use libfuzzer_sys::fuzz_target;

const FORMATS: [Format; 4] = [Format::Csv, Format::Xyz, Format::Ply, Format::Vtk];

fuzz_target!(|data: &[u8]| {
    let Some((&pick, body)) = data.split_first() else {
        return;
    };
    let format = FORMATS[usize::from(pick % 4)];
    let dim = [None, Some(2), Some(3)][usize::from(pick / 4 % 3)];
    match read_particles_from(body, "fuzz.in", format, &ReadOptions { dim, format: None }) {
        Ok(set) => {
            if let Some(d) = dim {
                assert_eq!(set.dim(), d);
            }
            for i in 0..set.len() {
                assert!(set.coords(i).iter().all(|c| c.is_finite()));
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(message.contains("fuzz.in"), "{message}");
            assert!(!message.contains('\n'), "{message}");
        }
    }
});
