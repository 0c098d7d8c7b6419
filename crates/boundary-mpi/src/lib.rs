//! The MPI-free parts of the `boundary-mpi` driver: the parallel decomposition
//! ([`parallel_rcb_owners`], [`parallel_morton_owners`] over a [`Reduce`]), the geometry of
//! the halo exchange and the reassembly of labels in input order. The binary (`src/main.rs`) moves the data between
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

use boundary::implement::{decompose, NeighbourGrid};
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

/// The sums, minima and maxima over all ranks that the parallel decomposition needs: every
/// rank calls the same reductions in the same order (MPI's all-reduce; [`Solo`] for one
/// process).
pub trait Reduce {
    /// Element-wise sum over the ranks, in place.
    fn sum(&self, values: &mut [u64]);
    /// Element-wise maximum over the ranks, in place.
    fn max_u64(&self, values: &mut [u64]);
    /// Element-wise minimum over the ranks, in place.
    fn min(&self, values: &mut [f64]);
}

/// One process: every reduction is the identity.
#[derive(Debug, Clone, Copy, Default)]
pub struct Solo;

impl Reduce for Solo {
    fn sum(&self, _: &mut [u64]) {}
    fn max_u64(&self, _: &mut [u64]) {}
    fn min(&self, _: &mut [f64]) {}
}

/// A key in `u64` order that is `f64::total_cmp`'s order of `x`.
pub fn ordered_bits(x: f64) -> u64 {
    let b = x.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | (1 << 63)
    }
}

/// One query of [`select`]: its remaining candidates on this rank, the rank sought among
/// them, the key bits found so far, and whether it is done.
struct Query {
    keys: Vec<u128>,
    target: u64,
    found: u128,
    /// The next digit's shift; the bits above it are in `found`.
    shift: u32,
    done: bool,
}

/// For each query `(keys, target)`, the key of global rank `target` (0-based, ascending)
/// among the union of every rank's `keys`: a radix selection with digits of 8 bits from the
/// top, each round's 256 counts summed over the ranks. The leading bits that the smallest
/// and the largest key share are skipped, and a query ends as soon as one candidate is left
/// (fetched by a maximum over the ranks), so a round count of about
/// `log_256(candidates) + 2` suffices for spread keys. Keys must be distinct over all ranks
/// (they carry the global index) and `target` below their global count; every rank passes
/// the same number of queries with the same targets.
pub fn select<R: Reduce>(reduce: &R, queries: Vec<(Vec<u128>, u64)>) -> Vec<u128> {
    if queries.is_empty() {
        return Vec::new();
    }
    // The shared leading bits of the high halves: the largest high half and the complement
    // of the smallest, over all ranks.
    let mut spread: Vec<u64> = queries
        .iter()
        .flat_map(|(keys, _)| {
            let hi = keys.iter().map(|&k| (k >> 64) as u64);
            [!hi.clone().min().unwrap_or(u64::MAX), hi.max().unwrap_or(0)]
        })
        .collect();
    reduce.max_u64(&mut spread);
    let mut queries: Vec<Query> = queries
        .into_iter()
        .zip(spread.chunks_exact(2))
        .map(|((keys, target), s)| {
            let (lo, hi) = (!s[0], s[1]);
            let digits = (lo ^ hi).leading_zeros() / 8; // 8: equal high halves
            let shift = 120 - 8 * digits;
            let known = if digits == 0 {
                0
            } else {
                (u128::from(lo) << 64) & (u128::MAX << (shift + 8))
            };
            Query {
                keys,
                target,
                found: known,
                shift,
                done: false,
            }
        })
        .collect();
    while queries.iter().any(|q| !q.done) {
        let active: Vec<usize> = (0..queries.len()).filter(|&k| !queries[k].done).collect();
        let mut counts = vec![0u64; 256 * active.len()];
        for (&k, hist) in active.iter().zip(counts.chunks_exact_mut(256)) {
            let q = &queries[k];
            for &key in &q.keys {
                hist[((key >> q.shift) & 0xff) as usize] += 1;
            }
        }
        reduce.sum(&mut counts);
        let mut last = Vec::new();
        for (&k, hist) in active.iter().zip(counts.chunks_exact(256)) {
            let q = &mut queries[k];
            let mut below = 0u64;
            let mut digit = 255usize;
            for (d, &c) in hist.iter().enumerate() {
                if below + c > q.target {
                    digit = d;
                    break;
                }
                below += c;
            }
            q.target -= below;
            q.found |= (digit as u128) << q.shift;
            let shift = q.shift;
            q.keys
                .retain(|&key| ((key >> shift) & 0xff) as usize == digit);
            if hist[digit] == 1 || shift == 0 {
                last.push(k);
            } else {
                q.shift -= 8;
            }
        }
        if !last.is_empty() {
            // One candidate left in each: the rank that holds it gives it, the others 0.
            let mut keys: Vec<u64> = last
                .iter()
                .flat_map(|&k| {
                    let key = queries[k].keys.first().copied().unwrap_or(0);
                    [(key >> 64) as u64, key as u64]
                })
                .collect();
            reduce.max_u64(&mut keys);
            for (&k, pair) in last.iter().zip(keys.chunks_exact(2)) {
                let q = &mut queries[k];
                q.found = (u128::from(pair[0]) << 64) | u128::from(pair[1]);
                q.done = true;
            }
        }
    }
    queries.into_iter().map(|q| q.found).collect()
}

/// The key that orders particles along `axis` as the core's RCB does: the coordinate
/// (`total_cmp`), ties by global index.
fn axis_key(coord: f64, index: u64) -> u128 {
    (u128::from(ordered_bits(coord)) << 64) | u128::from(index)
}

/// The owner of each local particle under recursive coordinate bisection of the particles of
/// all ranks into `parts` parts: exactly [`boundary::implement::decompose::rcb_owners`] of the
/// whole set in global-index order, computed without gathering it. Each level cuts every group
/// at once: its box and count by reduction, its cut by [`select`].
pub fn parallel_rcb_owners<const D: usize, R: Reduce>(
    reduce: &R,
    points: &[Point<D>],
    index: &[u64],
    parts: usize,
) -> Vec<usize> {
    struct Group {
        first: usize,
        parts: usize,
        members: Vec<usize>,
    }
    let mut owner = vec![0usize; points.len()];
    let mut active = vec![Group {
        first: 0,
        parts: parts.max(1),
        members: (0..points.len()).collect(),
    }];
    while !active.is_empty() {
        let g = active.len();
        let mut len: Vec<u64> = active.iter().map(|a| a.members.len() as u64).collect();
        // The boxes as minima: the low corners, then the negated high corners.
        let mut corners = vec![f64::INFINITY; 2 * g * D];
        for (k, a) in active.iter().enumerate() {
            for &m in &a.members {
                for d in 0..D {
                    let c = points[m][d];
                    corners[k * D + d] = corners[k * D + d].min(c);
                    corners[(g + k) * D + d] = corners[(g + k) * D + d].min(-c);
                }
            }
        }
        reduce.sum(&mut len);
        reduce.min(&mut corners);
        let (lo, hi) = corners.split_at(g * D);
        // (group, axis, low parts) of the groups cut at this level, and their queries.
        let mut cuts = Vec::new();
        let mut queries = Vec::new();
        let mut next = Vec::new();
        for (k, a) in active.into_iter().enumerate() {
            if a.parts <= 1 || len[k] <= 1 {
                for &m in &a.members {
                    owner[m] = a.first;
                }
                continue;
            }
            let side = |d: usize| -hi[k * D + d] - lo[k * D + d];
            let mut axis = 0;
            for d in 1..D {
                if side(d) > side(axis) {
                    axis = d;
                }
            }
            let low_parts = a.parts / 2;
            let cut = len[k] * low_parts as u64 / a.parts as u64;
            if cut == 0 {
                // Nothing on the low side: the high side takes every particle.
                next.push(Group {
                    first: a.first + low_parts,
                    parts: a.parts - low_parts,
                    members: a.members,
                });
                continue;
            }
            let keys = a
                .members
                .iter()
                .map(|&m| axis_key(points[m][axis], index[m]))
                .collect();
            queries.push((keys, cut));
            cuts.push((a, axis, low_parts));
        }
        let splitters = select(reduce, queries);
        for ((a, axis, low_parts), splitter) in cuts.into_iter().zip(splitters) {
            let (low, high): (Vec<usize>, Vec<usize>) = a
                .members
                .iter()
                .partition(|&&m| axis_key(points[m][axis], index[m]) < splitter);
            next.push(Group {
                first: a.first,
                parts: low_parts,
                members: low,
            });
            next.push(Group {
                first: a.first + low_parts,
                parts: a.parts - low_parts,
                members: high,
            });
        }
        active = next;
    }
    owner
}

/// The owner of each local particle under the Morton blocks of the particles of all ranks
/// (cells of side `cell`): exactly [`boundary::implement::decompose::morton_owners`] of the
/// whole set in global-index order. The bounding box's low corner by reduction, the first key
/// of every block by [`select`].
pub fn parallel_morton_owners<const D: usize, R: Reduce>(
    reduce: &R,
    points: &[Point<D>],
    index: &[u64],
    parts: usize,
    cell: f64,
) -> Vec<usize> {
    let parts = parts.max(1);
    let mut lo = [f64::INFINITY; D];
    for p in points {
        for d in 0..D {
            lo[d] = lo[d].min(p[d]);
        }
    }
    reduce.min(&mut lo);
    let mut n = [points.len() as u64];
    reduce.sum(&mut n);
    let n = n[0];
    let lo = Point::<D>::from_fn(|d, _| lo[d]);
    let keys: Vec<u128> = points
        .iter()
        .zip(index)
        .map(|(p, &i)| (u128::from(decompose::morton_key(p, &lo, cell)) << 64) | u128::from(i))
        .collect();
    // Block k starts at global rank k·n/parts; blocks that start past the end are empty.
    let starts: Vec<u64> = (1..parts as u64)
        .map(|k| k * n / parts as u64)
        .filter(|&s| s < n)
        .collect();
    let firsts = select(reduce, starts.iter().map(|&s| (keys.clone(), s)).collect());
    keys.iter()
        .map(|&key| firsts.iter().filter(|&&f| f <= key).count())
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

    /// Ranks simulated by threads: each reduction publishes this rank's values, waits for
    /// every rank, and combines them.
    struct Threads {
        rank: usize,
        shared: std::sync::Arc<Shared>,
    }

    struct Shared {
        barrier: std::sync::Barrier,
        ints: std::sync::Mutex<Vec<Vec<u64>>>,
        reals: std::sync::Mutex<Vec<Vec<f64>>>,
    }

    impl Threads {
        fn combine<T: Copy>(
            &self,
            slots: &std::sync::Mutex<Vec<Vec<T>>>,
            values: &mut [T],
            op: impl Fn(T, T) -> T,
        ) {
            slots.lock().unwrap()[self.rank] = values.to_vec();
            self.shared.barrier.wait();
            {
                let all = slots.lock().unwrap();
                for (k, v) in values.iter_mut().enumerate() {
                    *v = all.iter().map(|s| s[k]).reduce(&op).unwrap();
                }
            }
            self.shared.barrier.wait();
        }
    }

    impl Reduce for Threads {
        fn sum(&self, values: &mut [u64]) {
            self.combine(&self.shared.ints, values, |a, b| a + b);
        }
        fn max_u64(&self, values: &mut [u64]) {
            self.combine(&self.shared.ints, values, u64::max);
        }
        fn min(&self, values: &mut [f64]) {
            self.combine(&self.shared.reals, values, f64::min);
        }
    }

    /// Deals the particles of `pts` to `ranks` threads (rank `i * 7 % ranks` holds particle
    /// `i`, a split unlike any decomposition), runs `owners` on each and returns the owner of
    /// every particle in global order.
    fn owners_on_threads(
        pts: &[Point<2>],
        ranks: usize,
        owners: impl Fn(&Threads, &[Point<2>], &[u64]) -> Vec<usize> + Sync,
    ) -> Vec<usize> {
        let shared = std::sync::Arc::new(Shared {
            barrier: std::sync::Barrier::new(ranks),
            ints: std::sync::Mutex::new(vec![Vec::new(); ranks]),
            reals: std::sync::Mutex::new(vec![Vec::new(); ranks]),
        });
        let mut owner = vec![usize::MAX; pts.len()];
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..ranks)
                .map(|rank| {
                    let comm = Threads {
                        rank,
                        shared: shared.clone(),
                    };
                    let owners = &owners;
                    scope.spawn(move || {
                        let mine: Vec<usize> =
                            (0..pts.len()).filter(|i| i * 7 % ranks == rank).collect();
                        let local: Vec<Point<2>> = mine.iter().map(|&i| pts[i]).collect();
                        let index: Vec<u64> = mine.iter().map(|&i| i as u64).collect();
                        (mine, owners(&comm, &local, &index))
                    })
                })
                .collect();
            for h in handles {
                let (mine, got) = h.join().unwrap();
                for (i, o) in mine.into_iter().zip(got) {
                    owner[i] = o;
                }
            }
        });
        owner
    }

    /// A jittered lattice with duplicates, equal coordinates (ties by index) and negative
    /// values (the sign in the key order).
    fn scene(n: usize) -> Vec<Point<2>> {
        let mut pts: Vec<Point<2>> = (0..n)
            .map(|k| {
                let (i, j) = ((k % 23) as f64, (k / 23) as f64);
                p2(i - 11.0 + 0.37 * ((k * 7919) % 13) as f64 / 13.0, 4.0 - j)
            })
            .collect();
        if n > 40 {
            pts.extend_from_slice(&[pts[3], pts[40], pts[3]]);
        }
        pts
    }

    #[test]
    fn ordered_bits_follow_total_cmp() {
        let xs = [-f64::MAX, -2.5, -1.0, -0.0, 0.0, 1e-300, 1.0, 3.5, f64::MAX];
        for a in xs {
            for b in xs {
                assert_eq!(
                    ordered_bits(a).cmp(&ordered_bits(b)),
                    a.total_cmp(&b),
                    "{a} {b}"
                );
            }
        }
    }

    #[test]
    fn selection_finds_every_rank_of_the_sorted_keys() {
        let keys: Vec<u128> = (0..300u128)
            .map(|k| ((k * 2_654_435_761 % 1009) << 70) | k)
            .collect();
        let mut sorted = keys.clone();
        sorted.sort_unstable();
        let queries = (0..300u64).step_by(7).map(|t| (keys.clone(), t)).collect();
        let got = select(&Solo, queries);
        let want: Vec<u128> = (0..300).step_by(7).map(|t| sorted[t]).collect();
        assert_eq!(got, want);
        // Equal high halves (one coordinate): the order is the index's.
        let same: Vec<u128> = (0..50u128)
            .rev()
            .map(|k| (77u128 << 64) | (k * 3))
            .collect();
        let got = select(
            &Solo,
            vec![(same.clone(), 0), (same.clone(), 49), (same, 20)],
        );
        assert_eq!(
            got,
            [77u128 << 64, (77u128 << 64) | 147, (77u128 << 64) | 60]
        );
        // One key.
        assert_eq!(select(&Solo, vec![(vec![5u128], 0)]), [5]);
    }

    /// The parallel decompositions give the core's owners on any split across ranks and for
    /// any part count, more parts than particles included.
    #[test]
    fn parallel_decompositions_match_the_core_on_any_split() {
        for n in [0, 1, 5, 300] {
            let pts = scene(n);
            let set = ParticleSet::new(pts.clone()).unwrap();
            for parts in [1, 2, 3, 5, 8] {
                let expected = rcb_owners(&set, parts);
                for ranks in [1, 2, 3, 4] {
                    let got = owners_on_threads(&pts, ranks, |c, p, i| {
                        parallel_rcb_owners(c, p, i, parts)
                    });
                    assert_eq!(
                        got, expected,
                        "rcb: {n} points, {parts} parts, {ranks} ranks"
                    );
                }
                for cell in [0.7, 2.5, 0.0] {
                    let expected = decompose::morton_owners(&set, parts, cell);
                    for ranks in [1, 3] {
                        let got = owners_on_threads(&pts, ranks, |c, p, i| {
                            parallel_morton_owners(c, p, i, parts, cell)
                        });
                        if n == 0 {
                            assert!(got.is_empty() && expected.is_empty());
                        } else {
                            assert_eq!(got, expected, "morton {cell}: {n}, {parts}, {ranks}");
                        }
                    }
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
