//! Arbitrary bytes through every reader (CSV, XYZ, PLY, legacy VTK, VTU, VTP, BGEO, PySPH's
//! HDF5 and NPZ) with every
//! dimension option, positions only or with the point attributes: `Ok` or `Err`, never a panic
//! or an allocation sized by an unchecked header count; an error is one line naming the source;
//! a set read with `dim` given has that dimension; every kept attribute has one value per
//! particle.
#![no_main]

use boundary_io::{
    read_particle_file_from, read_particles_from, AttributeValues, Format, ReadOptions,
};
use libfuzzer_sys::fuzz_target;

const FORMATS: [Format; 9] = [
    Format::Csv,
    Format::Xyz,
    Format::Ply,
    Format::Vtk,
    Format::Vtu,
    Format::Vtp,
    Format::Bgeo,
    Format::Hdf5,
    Format::Npz,
];

fuzz_target!(|data: &[u8]| {
    let Some((&pick, body)) = data.split_first() else {
        return;
    };
    let format = FORMATS[usize::from(pick) % FORMATS.len()];
    let rest = usize::from(pick) / FORMATS.len();
    let dim = [None, Some(2), Some(3)][rest % 3];
    let attributes = rest / 3 % 2 == 1;
    let options = ReadOptions { dim, format: None };
    let result = if attributes {
        read_particle_file_from(body, "fuzz.in", format, &options).map(|file| {
            for a in &file.attributes {
                let len = match &a.values {
                    AttributeValues::Int(v) => v.len(),
                    AttributeValues::Float(v) => v.len(),
                };
                assert_eq!(len, file.set.len(), "{}", a.name);
            }
            file.set
        })
    } else {
        read_particles_from(body, "fuzz.in", format, &options)
    };
    match result {
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
