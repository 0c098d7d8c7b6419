//! The checks every uncertified method's `tests/against_exact.rs` runs against a reference
//! (`exact`, passed in by the caller: this crate does not depend on a method): the rim and
//! core of a jittered lattice ball, M floors on the shared scenes, and labels that do not
//! depend on the thread count or on a domain decomposition with the method's halo.
//!
//! Each check returns `Err` with a message naming the scene and the particle; the tests
//! `unwrap` it.

use crate::{SharedData, SHARED_SCENES};
use boundary_core::decompose::{morton_blocks, slabs};
use boundary_core::{BoundaryDetector, Confusion, Labels, ParticleSet, Radius};

/// The labels of `detector` on `set` at `r`.
pub fn labels<const D: usize>(
    detector: &dyn BoundaryDetector,
    set: &ParticleSet<D>,
    r: f64,
) -> Result<Labels, String>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let radius = Radius::new(r).map_err(|e| e.to_string())?;
    detector
        .detect(&set.to_any(), radius)
        .map(|d| d.labels)
        .map_err(|e| format!("{detector}: {e}"))
}

/// A lattice ball or disc of radius `radius` centred at the origin: the particles within 0.3
/// of its rim are all boundary, the particles deeper than `core_depth` all interior, and the
/// reference's boundary is found with recall `>= min_recall`.
pub fn check_ball<const D: usize>(
    method: &dyn BoundaryDetector,
    reference: &dyn BoundaryDetector,
    set: &ParticleSet<D>,
    radius: f64,
    r: f64,
    core_depth: f64,
    min_recall: f64,
) -> Result<Confusion, String>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let found = labels(method, set, r)?;
    let truth = labels(reference, set, r)?;
    for (i, p) in set.positions().iter().enumerate() {
        let depth = radius - p.norm();
        if depth < 0.3 && !found.is_boundary(i) {
            return Err(format!("{D}D {method}: rim particle {i} at depth {depth}"));
        }
        if depth > core_depth && found.is_boundary(i) {
            return Err(format!("{D}D {method}: deep particle {i} at depth {depth}"));
        }
    }
    let c =
        Confusion::from_labels(found.as_slice(), truth.as_slice()).map_err(|e| e.to_string())?;
    if c.recall() < min_recall {
        return Err(format!("{D}D {method}: recall below {min_recall}: {c:?}"));
    }
    Ok(c)
}

/// The confusion of `method` against `reference` on every shared scene named in `floors`,
/// failing when M is below the scene's floor (a missing data folder fails, unless
/// `BOUNDARY_ALLOW_MISSING_DATA=1` skips it). Prints each scene's Rec, FPR and M.
pub fn check_shared_floors(
    method: &dyn BoundaryDetector,
    reference: &dyn BoundaryDetector,
    floors: &[(&str, f64)],
) -> Result<(), String> {
    let data = SharedData::from_env();
    for &(name, dim, file, r, _, _, _) in SHARED_SCENES {
        let Some(&(_, floor)) = floors.iter().find(|f| f.0 == name) else {
            continue;
        };
        let pair = if dim == 2 {
            let Some(set) = data.set::<2>(file).map_err(|e| e.to_string())? else {
                continue;
            };
            (labels(method, &set, r)?, labels(reference, &set, r)?)
        } else {
            let Some(set) = data.set::<3>(file).map_err(|e| e.to_string())? else {
                continue;
            };
            (labels(method, &set, r)?, labels(reference, &set, r)?)
        };
        let c = Confusion::from_labels(pair.0.as_slice(), pair.1.as_slice())
            .map_err(|e| e.to_string())?;
        println!(
            "{name}: Rec {:.4} FPR {:.4} M {:.4}",
            c.recall(),
            c.fpr(),
            c.m()
        );
        if c.m() < floor {
            return Err(format!("{name} {method}: M {:.4} < {floor}", c.m()));
        }
    }
    Ok(())
}

/// On the shared 2D vortex frame: the same labels at 1 and 3 threads, from a slab and a
/// Morton decomposition with the method's `halo_width` (each part's owned particles through
/// `detect_owned`), and an error for more owned particles than the set holds.
pub fn check_threads_and_decomposition(method: &dyn BoundaryDetector) -> Result<(), String> {
    let data = SharedData::from_env();
    let Some(set) = data
        .set::<2>("particles2d/sandim_vortex_spin_frame_100_1698.csv")
        .map_err(|e| e.to_string())?
    else {
        return Ok(());
    };
    let r = Radius::new(0.022105).map_err(|e| e.to_string())?;
    let err = |e: boundary_core::DetectError| format!("{method}: {e}");
    let global = method.detect_2d(&set, r).map_err(err)?.labels;
    for threads in [1, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| e.to_string())?;
        let got = pool.install(|| method.detect_2d(&set, r)).map_err(err)?;
        if got.labels != global {
            return Err(format!("{method}: other labels at {threads} threads"));
        }
    }
    let halo = method.halo_width(r);
    let parts = [
        slabs(&set, 3, 0, halo).map_err(|e| e.to_string())?,
        morton_blocks(&set, 4, halo).map_err(|e| e.to_string())?,
    ];
    for subs in parts {
        let mut merged = vec![false; set.len()];
        for sub in &subs {
            let local = sub.particles(&set).to_any();
            let labels = method
                .detect_owned(&local, sub.owned.len(), r)
                .map_err(err)?
                .labels;
            if labels.len() != sub.owned.len() {
                return Err(format!(
                    "{method}: {} labels for {} owned",
                    labels.len(),
                    sub.owned.len()
                ));
            }
            for (k, &i) in sub.owned.iter().enumerate() {
                merged[i] = labels.is_boundary(k);
            }
        }
        if merged != global.as_slice() {
            return Err(format!("{method}: a decomposition changes the labels"));
        }
    }
    if method.detect_owned(&set.to_any(), set.len() + 1, r).is_ok() {
        return Err(format!(
            "{method}: more owned particles than the set holds accepted"
        ));
    }
    Ok(())
}
