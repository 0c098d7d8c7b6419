//! The MPI-free parts of the `boundary-mpi` driver: the geometry of the halo exchange and the
//! reassembly of labels in input order. The binary (`src/main.rs`) moves the data between
//! ranks; everything it decides is here, so that it is tested without `mpirun`.
//!
//! The exchange follows the classic two-step halo of particle codes. Each rank publishes the
//! bounding box of the particles it owns; it sends to rank `q` every owned particle within the
//! halo width `w` of `q`'s box ([`strip_for`]: a superset of what `q` needs, since a particle
//! within `w` of one of `q`'s particles is within `w` of their box), and keeps, of what it
//! receives, exactly the particles within `w` (closed, `d <= w`) of one of its own
//! ([`keep_ghosts`]): the ghosts of [`boundary::implement::decompose::Subdomain`] for the same owners.
//!
//! ```
//! use boundary::Point;
//! use boundary_mpi::{bounding_box, keep_ghosts, strip_for};
//!
//! // Rank A owns x = 0, 1, 2; rank B owns x = 3, 4 (all on y = 0). Halo width 1.5.
//! let a: Vec<Point<2>> = [0.0, 1.0, 2.0].iter().map(|&x| Point::<2>::new(x, 0.0)).collect();
//! let b: Vec<Point<2>> = [3.0, 4.0].iter().map(|&x| Point::<2>::new(x, 0.0)).collect();
//! let to_b = strip_for(&a, &bounding_box(&b).unwrap(), 1.5);
//! assert_eq!(to_b, vec![2]); // only x = 2 is within 1.5 of B's box [3, 4]
//! let ghosts = keep_ghosts(&b, &[a[2]], 1.5).unwrap();
//! assert_eq!(ghosts, vec![0]);
//! ```

use boundary::implement::NeighbourGrid;
use boundary::{CoreError, ParticleSet, Point};
use boundary::{Dim, SupportedDim};

/// Relative slack on `w²` when choosing the strip sent to another rank. The strip only has to
/// be a superset of the ghosts (the receiver keeps exactly those within `w`), and the box
/// distance sums its squares in another order than the neighbour grid's point distance, so a
/// particle at exactly `w` must not be lost to rounding.
pub const STRIP_SLACK: f64 = 1e-9;

/// An axis-aligned box `(lo, hi)`, `lo[k] <= hi[k]`.
pub type Aabb<const D: usize> = (Point<D>, Point<D>);

/// The bounding box of `points`, `None` for none.
pub fn bounding_box<const D: usize>(points: &[Point<D>]) -> Option<Aabb<D>> {
    let first = points.first()?;
    let mut lo = *first;
    let mut hi = *first;
    for p in points {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    Some((lo, hi))
}

/// Squared distance from `p` to the box (0 inside).
pub fn box_distance2<const D: usize>(p: &Point<D>, b: &Aabb<D>) -> f64 {
    let mut d2 = 0.0;
    for k in 0..D {
        let d = (b.0[k] - p[k]).max(p[k] - b.1[k]).max(0.0);
        d2 += d * d;
    }
    d2
}

/// Indices (into `owned`) of the particles to send to a rank whose owned particles have the
/// bounding box `other`: those within `w` of it (with [`STRIP_SLACK`]), ascending.
pub fn strip_for<const D: usize>(owned: &[Point<D>], other: &Aabb<D>, w: f64) -> Vec<usize> {
    let limit = w * w * (1.0 + STRIP_SLACK);
    owned
        .iter()
        .enumerate()
        .filter(|(_, p)| box_distance2(p, other) <= limit)
        .map(|(i, _)| i)
        .collect()
}

/// Indices (into `candidates`) of the candidates within `w` (closed, the neighbour grid's
/// `d² <= w²`) of at least one `owned` particle, ascending. These are exactly the ghosts that
/// [`boundary::implement::decompose::with_halo`] gives the same owned set.
///
/// Errors: `w` not positive and finite, or a scene the grid cannot index at cell size `w`.
pub fn keep_ghosts<const D: usize>(
    owned: &[Point<D>],
    candidates: &[Point<D>],
    w: f64,
) -> Result<Vec<usize>, CoreError>
where
    Dim<D>: SupportedDim,
{
    if owned.is_empty() || candidates.is_empty() {
        return Ok(Vec::new());
    }
    let set = ParticleSet::new(owned.to_vec())?;
    let grid = NeighbourGrid::new(&set, w)?;
    Ok(candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| {
            let mut near = false;
            grid.for_each_within(c, w, |_, _| near = true);
            near
        })
        .map(|(j, _)| j)
        .collect())
}

/// Puts labels that come as `(global index, label)` pairs, in any order, back in input order.
///
/// Errors (naming the index): an index `>= n`, an index given twice, an index never given.
pub fn labels_in_input_order(n: usize, indices: &[u64], labels: &[u8]) -> Result<Vec<u8>, String> {
    if indices.len() != labels.len() {
        return Err(format!(
            "{} indices but {} labels",
            indices.len(),
            labels.len()
        ));
    }
    const UNSET: u8 = u8::MAX;
    let mut out = vec![UNSET; n];
    for (&i, &label) in indices.iter().zip(labels) {
        let slot = usize::try_from(i)
            .ok()
            .and_then(|i| out.get_mut(i))
            .ok_or_else(|| format!("global index {i} out of range (the set has {n} particles)"))?;
        if *slot != UNSET {
            return Err(format!("global index {i} is owned by two ranks"));
        }
        *slot = label;
    }
    if let Some(missing) = out.iter().position(|&l| l == UNSET) {
        return Err(format!(
            "global index {missing} has no label (owned by no rank)"
        ));
    }
    Ok(out)
}

/// The path of rank `rank` for a per-rank pattern: every `{rank}` replaced by the rank.
///
/// Errors: a pattern without `{rank}` (all ranks would share one file).
pub fn rank_path(pattern: &str, rank: i32) -> Result<String, String> {
    if !pattern.contains("{rank}") {
        return Err(format!(
            "per-rank pattern {pattern:?} has no {{rank}} (every rank would use the same file)"
        ));
    }
    Ok(pattern.replace("{rank}", &rank.to_string()))
}

/// Global indices from a column of reals (as a CSV column reads): each must be a non-negative
/// integer below 2^53. Errors name the row (0-based particle index in the file) and `file`.
pub fn global_indices(values: &[f64], file: &str) -> Result<Vec<u64>, String> {
    const LIMIT: f64 = 9_007_199_254_740_992.0; // 2^53: every integer below is exact in f64
    values
        .iter()
        .enumerate()
        .map(|(row, &v)| {
            if v.fract() == 0.0 && (0.0..LIMIT).contains(&v) {
                Ok(v as u64)
            } else {
                Err(format!(
                    "{file}: particle {row}: index {v} is not a non-negative integer below 2^53"
                ))
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
    use super::*;
    use boundary::implement::decompose::{rcb_owners, with_halo};

    fn p2(x: f64, y: f64) -> Point<2> {
        Point::<2>::new(x, y)
    }

    #[test]
    fn box_distance_is_zero_inside_and_euclidean_outside() {
        let b = (p2(0.0, 0.0), p2(1.0, 2.0));
        assert_eq!(box_distance2(&p2(0.5, 1.0), &b), 0.0);
        assert_eq!(box_distance2(&p2(1.0, 2.0), &b), 0.0);
        assert_eq!(box_distance2(&p2(4.0, 6.0), &b), 9.0 + 16.0);
        assert_eq!(box_distance2(&p2(-2.0, 1.0), &b), 4.0);
    }

    #[test]
    fn a_particle_at_exactly_w_is_sent_and_kept() {
        let owned = [p2(0.0, 0.0)];
        let other = [p2(3.0, 4.0)];
        let b = bounding_box(&other).unwrap();
        assert_eq!(strip_for(&owned, &b, 5.0), vec![0]);
        assert_eq!(keep_ghosts(&other, &owned, 5.0).unwrap(), vec![0]);
        assert!(strip_for(&owned, &b, 4.999).is_empty());
        assert!(keep_ghosts(&other, &owned, 4.999).unwrap().is_empty());
    }

    /// Replays the exchange for every rank of an RCB split and compares the ghosts with the
    /// core's `with_halo` on the whole set.
    #[test]
    fn exchange_gives_the_ghosts_of_the_core_decomposition() {
        // A jittered 20 x 15 lattice (deterministic jitter, no RNG) with duplicates.
        let mut pts: Vec<Point<2>> = (0..300)
            .map(|k| {
                let (i, j) = ((k % 20) as f64, (k / 20) as f64);
                p2(i + 0.13 * ((k * 7919) % 11) as f64 / 11.0, j)
            })
            .collect();
        pts.extend_from_slice(&[pts[17], pts[170]]);
        let set = ParticleSet::new(pts.clone()).unwrap();
        for parts in [2, 3, 5, 8] {
            for w in [0.5, 1.0, 2.5] {
                let owner = rcb_owners(&set, parts);
                let expected = with_halo(&set, &owner, parts, w).unwrap();
                let owned: Vec<Vec<usize>> = (0..parts)
                    .map(|q| (0..pts.len()).filter(|&i| owner[i] == q).collect())
                    .collect();
                let pos =
                    |ids: &[usize]| -> Vec<Point<2>> { ids.iter().map(|&i| pts[i]).collect() };
                for me in 0..parts {
                    let mine = pos(&owned[me]);
                    let Some(my_box) = bounding_box(&mine) else {
                        continue;
                    };
                    let mut received: Vec<usize> = Vec::new();
                    for (q, theirs) in owned.iter().enumerate() {
                        if q != me {
                            let sent = strip_for(&pos(theirs), &my_box, w);
                            received.extend(sent.iter().map(|&k| theirs[k]));
                        }
                    }
                    let kept = keep_ghosts(&mine, &pos(&received), w).unwrap();
                    let mut ghosts: Vec<usize> = kept.iter().map(|&k| received[k]).collect();
                    ghosts.sort_unstable();
                    assert_eq!(
                        ghosts, expected[me].ghosts,
                        "{parts} parts, w {w}, rank {me}"
                    );
                }
            }
        }
    }

    #[test]
    fn labels_come_back_in_input_order_and_bad_indices_are_named() {
        assert_eq!(
            labels_in_input_order(4, &[2, 0, 3, 1], &[1, 0, 1, 0]).unwrap(),
            vec![0, 0, 1, 1]
        );
        let twice = labels_in_input_order(3, &[0, 1, 1], &[0, 0, 0]).unwrap_err();
        assert!(twice.contains("index 1"), "{twice}");
        let missing = labels_in_input_order(3, &[0, 2], &[0, 0]).unwrap_err();
        assert!(missing.contains("index 1"), "{missing}");
        let out = labels_in_input_order(2, &[0, 5], &[0, 0]).unwrap_err();
        assert!(out.contains("index 5"), "{out}");
        assert!(labels_in_input_order(1, &[0], &[]).is_err());
    }

    #[test]
    fn rank_paths_and_index_columns() {
        assert_eq!(rank_path("part_{rank}.csv", 3).unwrap(), "part_3.csv");
        assert!(rank_path("part.csv", 0).is_err());
        assert_eq!(global_indices(&[0.0, 7.0], "f").unwrap(), vec![0, 7]);
        let e = global_indices(&[0.0, 1.5], "f.csv").unwrap_err();
        assert!(e.contains("f.csv: particle 1"), "{e}");
        assert!(global_indices(&[-1.0], "f").is_err());
        assert!(global_indices(&[f64::NAN], "f").is_err());
    }
}
