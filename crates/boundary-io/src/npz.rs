//! PySPH's `.npz` output (what PySPH writes without h5py): a NumPy zip archive whose
//! `particles` entry is one pickled Python dictionary of every particle array ("version 2").
//! Reading pickles is not done here: the error names the conversions that work.

use crate::error::{IoError, Location};
use crate::pysph::ParticleArray;

/// Refuses the file with the ways to read it.
pub(crate) fn read(_bytes: &[u8], name: &str) -> Result<Vec<ParticleArray>, IoError> {
    Err(IoError::parse(
        name,
        Location::File,
        "PySPH's .npz output (pickled Python dictionaries) is not read: run PySPH with h5py \
         installed (pip install h5py), which makes it write .hdf5, or convert the file with \
         `pysph dump_vtk` to .vtu",
    ))
}
