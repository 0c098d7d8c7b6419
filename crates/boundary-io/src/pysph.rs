//! PySPH's own output: `.hdf5` (what PySPH writes when h5py is installed, its default) and
//! `.npz` (what it writes otherwise). Both hold one or more *particle arrays* (`fluid`,
//! `boundary`, `solid`, …), each a set of named properties with one value per particle
//! (`x`, `y`, `z`, `h`, `m`, `rho`, `gid`, …), some with `stride` values per particle.
//!
//! ```text
//! .hdf5  /particles/<array>/arrays/<property>   one dataset per property (length 0 when the
//!                                               property is declared but not output)
//!        /particles/<array>/constants/<name>    per-array constants (not read)
//!        /solver_data                           attributes t, dt, count (not read)
//! ```
//!
//! The HDF5 file is read with the pure-Rust `hdf5-pure` crate (no HDF5 library needed); the
//! `.npz` layout in the `npz` module.
//!
//! One array is read at a time: the one asked for, else `fluid`, else the file's only array.
//! Its positions are `x`, `y` and, when present, `z`; PySPH keeps `z` = 0 for a 2D run, so an
//! all-zero `z` reads as a 2D set (as for VTK written by this crate), and `dim = 3` keeps it.
//! Every other property with one value per particle is an attribute (reals as reals, integers
//! as integers); a property of `k` values per particle becomes `name:0` … `name:k-1`; a
//! property not output (no value) is left out.

use crate::error::{IoError, Location};
use crate::{Attribute, AttributeValues, LineIndex, Positions};
use std::io::Read;

/// The array read when none is named and the file holds several.
pub(crate) const DEFAULT_ARRAY: &str = "fluid";

/// One particle array of a PySPH file: its properties in file order.
#[derive(Debug)]
pub(crate) struct ParticleArray {
    pub name: String,
    pub properties: Vec<(String, PropertyValues)>,
}

/// A property's values as the file stores them.
#[derive(Debug)]
pub(crate) enum PropertyValues {
    Int(Vec<i64>),
    Float(Vec<f64>),
    /// A type that is neither integer nor real, with its description.
    Other(String),
}

impl PropertyValues {
    fn len(&self) -> usize {
        match self {
            PropertyValues::Int(v) => v.len(),
            PropertyValues::Float(v) => v.len(),
            PropertyValues::Other(_) => 0,
        }
    }
}

/// The particle arrays of a PySPH file, with their particle counts (the length of `x`), in
/// file order.
pub(crate) fn list(arrays: &[ParticleArray]) -> Vec<(String, usize)> {
    arrays
        .iter()
        .map(|a| {
            let n = a
                .properties
                .iter()
                .find(|(p, _)| p == "x")
                .map_or(0, |(_, v)| v.len());
            (a.name.clone(), n)
        })
        .collect()
}

/// Reads every particle array of the HDF5 file in `bytes`.
pub(crate) fn read_hdf5(bytes: Vec<u8>, name: &str) -> Result<Vec<ParticleArray>, IoError> {
    let bad = |what: String| IoError::parse(name, Location::File, what);
    let file = hdf5_pure::File::from_bytes(bytes)
        .map_err(|e| bad(format!("not a readable HDF5 file ({e})")))?;
    let particles = file.group("particles").map_err(|e| {
        bad(format!(
            "no group /particles, so not PySPH output (PySPH writes each particle array under \
             /particles/<array>/arrays): {e}"
        ))
    })?;
    let names = particles.groups().map_err(|e| {
        bad(format!(
            "cannot list the particle arrays of /particles: {e}"
        ))
    })?;
    let mut arrays = Vec::with_capacity(names.len());
    for array in names {
        let at = format!("/particles/{array}/arrays");
        let group = particles
            .group(&array)
            .and_then(|g| g.group("arrays"))
            .map_err(|e| bad(format!("particle array {array:?}: no group {at} ({e})")))?;
        let props = group
            .datasets()
            .map_err(|e| bad(format!("particle array {array:?}: cannot list {at} ({e})")))?;
        let mut properties = Vec::with_capacity(props.len());
        for prop in props {
            let fail = |e: hdf5_pure::Error| {
                bad(format!(
                    "particle array {array:?}: cannot read property {prop:?} ({at}/{prop}): {e}"
                ))
            };
            let ds = group.dataset(&prop).map_err(fail)?;
            let values = match ds.dtype().map_err(fail)? {
                hdf5_pure::DType::F32 | hdf5_pure::DType::F64 => {
                    PropertyValues::Float(ds.read_f64().map_err(fail)?)
                }
                hdf5_pure::DType::I8
                | hdf5_pure::DType::I16
                | hdf5_pure::DType::I32
                | hdf5_pure::DType::I64
                | hdf5_pure::DType::U8
                | hdf5_pure::DType::U16
                | hdf5_pure::DType::U32 => PropertyValues::Int(ds.read_i64().map_err(fail)?),
                hdf5_pure::DType::U64 => {
                    let v = ds.read_u64().map_err(fail)?;
                    if v.iter().all(|&x| i64::try_from(x).is_ok()) {
                        PropertyValues::Int(v.into_iter().map(|x| x as i64).collect())
                    } else {
                        PropertyValues::Float(v.into_iter().map(|x| x as f64).collect())
                    }
                }
                other => PropertyValues::Other(other.to_string()),
            };
            properties.push((prop, values));
        }
        arrays.push(ParticleArray {
            name: array,
            properties,
        });
    }
    Ok(arrays)
}

/// Reads the whole of `reader` and parses it as `format`'s layout.
pub(crate) fn read_arrays(
    mut reader: impl Read,
    name: &str,
    npz: bool,
) -> Result<Vec<ParticleArray>, IoError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::read(name, e))?;
    if npz {
        crate::npz::read(&bytes, name)
    } else {
        read_hdf5(bytes, name)
    }
}

/// The positions and attributes of the array `wanted` (else the default, see the module
/// docs) of a PySPH file.
pub(crate) fn read(
    reader: impl Read,
    name: &str,
    npz: bool,
    wanted: Option<&str>,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let arrays = read_arrays(reader, name, npz)?;
    select(arrays, name, wanted, with_attributes)
}

fn describe(arrays: &[ParticleArray]) -> String {
    let names: Vec<String> = list(arrays)
        .into_iter()
        .map(|(a, n)| format!("{a} ({n} particles)"))
        .collect();
    names.join(", ")
}

/// The positions and attributes of one array, chosen as the module docs say.
pub(crate) fn select(
    mut arrays: Vec<ParticleArray>,
    name: &str,
    wanted: Option<&str>,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let bad = |what: String| IoError::parse(name, Location::File, what);
    if arrays.is_empty() {
        return Err(IoError::NoParticles {
            file: name.to_owned(),
            dim: None,
            detail: "it holds no particle array".to_owned(),
        });
    }
    let index = match wanted {
        Some(w) => arrays.iter().position(|a| a.name == w).ok_or_else(|| {
            bad(format!(
                "no particle array {w:?}; the file holds {}",
                describe(&arrays)
            ))
        })?,
        None => match arrays.iter().position(|a| a.name == DEFAULT_ARRAY) {
            Some(i) => i,
            None if arrays.len() == 1 => 0,
            None => {
                return Err(bad(format!(
                    "no particle array {DEFAULT_ARRAY:?} and several others, so which to read \
                     is unclear (name one: read_particle_array); the file holds {}",
                    describe(&arrays)
                )))
            }
        },
    };
    let array = arrays.swap_remove(index);
    let axis = |p: &str| -> Result<Option<Vec<f64>>, IoError> {
        match array.properties.iter().find(|(n, _)| n == p) {
            None => Ok(None),
            Some((_, PropertyValues::Float(v))) => Ok(Some(v.clone())),
            Some((_, PropertyValues::Int(v))) => Ok(Some(v.iter().map(|&x| x as f64).collect())),
            Some((_, PropertyValues::Other(t))) => Err(bad(format!(
                "particle array {:?}: position property {p:?} holds {t}, not numbers",
                array.name
            ))),
        }
    };
    let (Some(x), Some(y)) = (axis("x")?, axis("y")?) else {
        return Err(bad(format!(
            "particle array {:?} has no position properties x and y",
            array.name
        )));
    };
    let z = axis("z")?;
    let n = x.len();
    for (p, v) in [("y", Some(&y)), ("z", z.as_ref())] {
        if let Some(v) = v {
            if v.len() != n {
                return Err(bad(format!(
                    "particle array {:?}: property {p:?} has {} values but x has {n}",
                    array.name,
                    v.len()
                )));
            }
        }
    }
    let stride = if z.is_some() { 3 } else { 2 };
    let mut coords = Vec::with_capacity(n * stride);
    for i in 0..n {
        for (axis, value) in [Some(x[i]), Some(y[i]), z.as_ref().map(|z| z[i])]
            .into_iter()
            .flatten()
            .enumerate()
        {
            if !value.is_finite() {
                return Err(IoError::NonFinite {
                    file: name.to_owned(),
                    at: Location::Item {
                        kind: "particle",
                        index: i,
                    },
                    index: i,
                    axis,
                    value,
                });
            }
            coords.push(value);
        }
    }
    let mut names = vec!["x".to_owned(), "y".to_owned()];
    if z.is_some() {
        names.push("z".to_owned());
    }
    let mut attributes: Vec<Attribute> = Vec::new();
    let mut skipped = Vec::new();
    if with_attributes {
        for (prop, values) in array.properties {
            if matches!(prop.as_str(), "x" | "y" | "z") {
                continue;
            }
            let len = values.len();
            if len == 0 {
                if let PropertyValues::Other(t) = values {
                    skipped.push(format!("{prop}: holds {t}, not numbers"));
                }
                // Declared but not output: PySPH stores no value.
                continue;
            }
            if n == 0 || len % n != 0 {
                skipped.push(format!(
                    "{prop}: {len} values for {n} particles (not a whole number per particle)"
                ));
                continue;
            }
            let k = len / n;
            let column = crate::attribute_name(&prop, attributes.len());
            let parts: Vec<(String, AttributeValues)> = match values {
                PropertyValues::Int(v) if k == 1 => vec![(column, AttributeValues::Int(v))],
                PropertyValues::Float(v) if k == 1 => vec![(column, AttributeValues::Float(v))],
                PropertyValues::Int(v) => (0..k)
                    .map(|c| {
                        let part = v.iter().skip(c).step_by(k).copied().collect();
                        (format!("{column}:{c}"), AttributeValues::Int(part))
                    })
                    .collect(),
                PropertyValues::Float(v) => (0..k)
                    .map(|c| {
                        let part = v.iter().skip(c).step_by(k).copied().collect();
                        (format!("{column}:{c}"), AttributeValues::Float(part))
                    })
                    .collect(),
                PropertyValues::Other(_) => Vec::new(),
            };
            for (column, values) in parts {
                match crate::attribute_conflict(&column, &attributes) {
                    Some(why) => skipped.push(format!("{prop}: {why}")),
                    None => attributes.push(Attribute {
                        name: column,
                        values,
                    }),
                }
            }
        }
    }
    Ok(Positions {
        coords,
        stride,
        padded_2d: z.is_some(),
        attributes,
        skipped,
        names,
        near_miss: None,
        empty: (n == 0).then(|| format!("its particle array {:?} is empty", array.name)),
        // HDF5 and NPZ have no lines.
        lines: LineIndex::default(),
    })
}
