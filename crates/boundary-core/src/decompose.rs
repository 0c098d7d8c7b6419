//! Domain decomposition with halos, for simulations split across processes.
//!
//! A [`Subdomain`] owns some particles and holds, as *ghosts*, every other particle within the
//! halo width of an owned one. A detector whose decision for particle `i` depends only on the
//! particles within `w` of `p_i` ([`crate::BoundaryDetector::halo_width`]) gives the owned
//! particles of a subdomain with halo `w` exactly the labels of the global run. Subdomain
//! particle sets list owned particles first, then ghosts; see
//! [`crate::BoundaryDetector::detect_owned`].
//!
//! Two decompositions, both balanced by particle count: slabs along one axis, and blocks of
//! consecutive particles in Morton (Z-order) of their cells.

use crate::{CoreError, NeighbourGrid, ParticleSet, Point};

/// One part of a decomposition: global indices of its owned particles and of its ghosts.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Subdomain {
    /// Particles this part classifies (global indices, ascending).
    pub owned: Vec<usize>,
    /// Other particles within the halo width of an owned one (global indices, ascending).
    pub ghosts: Vec<usize>,
}

impl Subdomain {
    /// The local particle set: owned particles first (in `owned` order), then ghosts.
    pub fn particles<const D: usize>(&self, set: &ParticleSet<D>) -> ParticleSet<D> {
        let order: Vec<usize> = self.owned.iter().chain(&self.ghosts).copied().collect();
        set.subset(&order)
    }
}

/// The owner of each particle when `order` (a permutation of the particles) is cut into
/// `parts` runs of nearly equal length (run `k` is `order[k n / parts .. (k + 1) n / parts]`).
fn owners_of_runs(order: &[usize], parts: usize) -> Vec<usize> {
    let parts = parts.max(1);
    let n = order.len();
    let mut owner = vec![0usize; n];
    for k in 0..parts {
        for &i in &order[k * n / parts..(k + 1) * n / parts] {
            owner[i] = k;
        }
    }
    owner
}

/// Builds the subdomains of a given assignment: part `owner[i]` owns particle `i`, and holds as
/// ghosts every particle of another part within `halo` (closed: `d <= halo`) of one it owns.
///
/// Errors: `owner` not one entry per particle, an owner `>= parts`, or a `halo` the neighbour
/// grid rejects (not positive and finite).
pub fn with_halo<const D: usize>(
    set: &ParticleSet<D>,
    owner: &[usize],
    parts: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    let parts = parts.max(1);
    let n = set.len();
    if owner.len() != n {
        return Err(CoreError::InvalidDecomposition(format!(
            "{} owners for {n} particles",
            owner.len()
        )));
    }
    let mut subs: Vec<Subdomain> = (0..parts).map(|_| Subdomain::default()).collect();
    for (i, &rank) in owner.iter().enumerate() {
        let sub = subs.get_mut(rank).ok_or_else(|| {
            CoreError::InvalidDecomposition(format!(
                "particle {i} has owner {rank}, but there are {parts} parts"
            ))
        })?;
        sub.owned.push(i);
    }
    if n == 0 {
        return Ok(subs);
    }
    let grid = NeighbourGrid::new(set, halo)?;
    let mut mark = vec![usize::MAX; n];
    for (rank, sub) in subs.iter_mut().enumerate() {
        for &i in &sub.owned {
            grid.for_each_within(&set.positions()[i], halo, |j, _| {
                if owner[j] != rank && mark[j] != rank {
                    mark[j] = rank;
                    sub.ghosts.push(j);
                }
            });
        }
        sub.ghosts.sort_unstable();
    }
    Ok(subs)
}

/// Owners of `parts` slabs along `axis`, balanced by count (particles sorted by that
/// coordinate, ties by index).
pub fn slab_owners<const D: usize>(set: &ParticleSet<D>, parts: usize, axis: usize) -> Vec<usize> {
    let axis = axis.min(D - 1);
    let p = set.positions();
    let mut order: Vec<usize> = (0..set.len()).collect();
    order.sort_by(|&a, &b| p[a][axis].total_cmp(&p[b][axis]).then(a.cmp(&b)));
    owners_of_runs(&order, parts)
}

/// `parts` slabs along `axis`, balanced by count (particles sorted by that coordinate, ties
/// by index), each with its ghosts within `halo`.
pub fn slabs<const D: usize>(
    set: &ParticleSet<D>,
    parts: usize,
    axis: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    with_halo(set, &slab_owners(set, parts, axis), parts, halo)
}

/// Interleaves the bits of the cell coordinates (21 bits per axis in 3D, 32 in 2D).
fn morton<const D: usize>(cell: [u64; D]) -> u64 {
    let bits = 64 / D as u32;
    let mut code = 0u64;
    for b in 0..bits {
        for (k, c) in cell.iter().enumerate() {
            code |= ((c >> b) & 1) << (b as usize * D + k);
        }
    }
    code
}

/// The Morton code of the cell of `p` among cells of side `cell` counted from `lo` (the low
/// corner of the set's bounding box) and clamped to 2·10^6 cells per axis: the key of
/// [`morton_owners`]. A `cell` that is not positive and finite puts every point in cell 0.
pub fn morton_key<const D: usize>(p: &Point<D>, lo: &Point<D>, cell: f64) -> u64 {
    let ok = cell.is_finite() && cell > 0.0;
    morton::<D>(std::array::from_fn(|k| {
        if ok {
            ((p[k] - lo[k]) / cell).floor().clamp(0.0, 2e6) as u64
        } else {
            0
        }
    }))
}

/// Owners of `parts` blocks of consecutive particles in Morton order of their cells (side
/// `cell`, counted from the bounding box's low corner and clamped to 2·10^6 cells per axis;
/// ties in the code by index), balanced by count. A `cell` that is not positive and finite
/// puts every particle in cell 0 (the blocks are then runs of indices).
pub fn morton_owners<const D: usize>(set: &ParticleSet<D>, parts: usize, cell: f64) -> Vec<usize> {
    let Some((lo, _)) = set.bounding_box() else {
        return Vec::new();
    };
    let p = set.positions();
    let mut keyed: Vec<(u64, usize)> = (0..set.len())
        .map(|i| (morton_key(&p[i], &lo, cell), i))
        .collect();
    keyed.sort_unstable();
    let order: Vec<usize> = keyed.into_iter().map(|(_, i)| i).collect();
    owners_of_runs(&order, parts)
}

/// `parts` blocks of consecutive particles in Morton order of their cells (side `halo`),
/// balanced by count, each with its ghosts within `halo`.
pub fn morton_blocks<const D: usize>(
    set: &ParticleSet<D>,
    parts: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    with_halo(set, &morton_owners(set, parts, halo), parts, halo)
}

/// Owners by recursive coordinate bisection (Berger & Bokhari 1987), balanced by count: a
/// group of particles meant for `q` parts is cut across the longest side of its bounding box
/// (ties: the lower axis) so that the low side holds `⌊len·⌊q/2⌋/q⌋` particles (ordered by that
/// coordinate, ties by index, so the cut is unique), and each side is cut again for its share
/// of the parts. Parts are numbered low side first. Part sizes differ by at most one.
///
/// ```
/// use boundary_core::decompose::{rcb_owners, with_halo};
/// use boundary_core::ParticleSet;
///
/// // A 4 x 2 strip is cut across x into two 2 x 2 squares.
/// let rows: Vec<[f64; 2]> = (0..8).map(|k| [(k / 2) as f64, (k % 2) as f64]).collect();
/// let set = ParticleSet::from_rows(&rows).unwrap();
/// let owner = rcb_owners(&set, 2);
/// assert_eq!(owner, vec![0, 0, 0, 0, 1, 1, 1, 1]);
/// // With a halo of 1, each square sees the facing column of the other as ghosts.
/// let subs = with_halo(&set, &owner, 2, 1.0).unwrap();
/// assert_eq!(subs[0].ghosts, vec![4, 5]);
/// assert_eq!(subs[1].ghosts, vec![2, 3]);
/// ```
pub fn rcb_owners<const D: usize>(set: &ParticleSet<D>, parts: usize) -> Vec<usize> {
    let mut owner = vec![0usize; set.len()];
    let mut idx: Vec<usize> = (0..set.len()).collect();
    bisect(set.positions(), &mut idx, parts.max(1), 0, &mut owner);
    owner
}

fn bisect<const D: usize>(
    p: &[Point<D>],
    idx: &mut [usize],
    parts: usize,
    first: usize,
    owner: &mut [usize],
) {
    if parts <= 1 || idx.len() <= 1 {
        for &i in idx.iter() {
            owner[i] = first;
        }
        return;
    }
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for &i in idx.iter() {
        for k in 0..D {
            lo[k] = lo[k].min(p[i][k]);
            hi[k] = hi[k].max(p[i][k]);
        }
    }
    let mut axis = 0;
    for k in 1..D {
        if hi[k] - lo[k] > hi[axis] - lo[axis] {
            axis = k;
        }
    }
    let low_parts = parts / 2;
    let cut = idx.len() * low_parts / parts;
    if cut > 0 {
        idx.select_nth_unstable_by(cut, |&a, &b| {
            p[a][axis].total_cmp(&p[b][axis]).then(a.cmp(&b))
        });
    }
    let (low, high) = idx.split_at_mut(cut);
    bisect(p, low, low_parts, first, owner);
    bisect(p, high, parts - low_parts, first + low_parts, owner);
}

/// `parts` boxes by recursive coordinate bisection ([`rcb_owners`]), each with its ghosts
/// within `halo`.
pub fn rcb<const D: usize>(
    set: &ParticleSet<D>,
    parts: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    with_halo(set, &rcb_owners(set, parts), parts, halo)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(n: usize) -> ParticleSet<3> {
        ParticleSet::new(
            (0..n * n * n)
                .map(|k| {
                    Point::<3>::new((k % n) as f64, ((k / n) % n) as f64, (k / (n * n)) as f64)
                })
                .collect(),
        )
        .unwrap()
    }

    fn check_partition(set: &ParticleSet<3>, subs: &[Subdomain], halo: f64) {
        let mut owned = vec![0; set.len()];
        for s in subs {
            for &i in &s.owned {
                owned[i] += 1;
            }
            // Every ghost is within the halo of an owned particle and not owned here; every
            // particle within the halo of an owned one is owned here or a ghost.
            for j in 0..set.len() {
                let near = s
                    .owned
                    .iter()
                    .any(|&i| (set.positions()[i] - set.positions()[j]).norm() <= halo);
                let is_owned = s.owned.contains(&j);
                assert_eq!(s.ghosts.contains(&j), near && !is_owned, "particle {j}");
            }
            let local = s.particles(set);
            assert_eq!(local.len(), s.owned.len() + s.ghosts.len());
            assert_eq!(local.positions()[0], set.positions()[s.owned[0]]);
        }
        assert!(owned.iter().all(|&c| c == 1));
        let sizes: Vec<usize> = subs.iter().map(|s| s.owned.len()).collect();
        let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
        assert!(max - min <= 1, "{sizes:?}");
    }

    #[test]
    fn slabs_and_blocks_partition_and_collect_the_halo() {
        let set = lattice(6);
        for parts in [1, 2, 3, 8] {
            check_partition(&set, &slabs(&set, parts, 0, 1.5).unwrap(), 1.5);
            check_partition(&set, &morton_blocks(&set, parts, 1.5).unwrap(), 1.5);
            check_partition(&set, &rcb(&set, parts, 1.5).unwrap(), 1.5);
        }
    }

    #[test]
    fn rcb_parts_differ_by_at_most_one_and_cut_the_longest_side() {
        for n in 0..40 {
            let set = ParticleSet::<2>::new(
                (0..n)
                    .map(|k| Point::<2>::new((k % 7) as f64, (k / 7) as f64))
                    .collect(),
            )
            .unwrap();
            for parts in 1..12 {
                let owner = rcb_owners(&set, parts);
                let mut sizes = vec![0usize; parts];
                for &o in &owner {
                    sizes[o] += 1;
                }
                let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(max - min <= 1, "n {n}, parts {parts}: {sizes:?}");
            }
        }
        // A 10 x 2 strip is cut across x: the low half has x < 5 (ties at the cut by index).
        let strip = ParticleSet::<2>::new(
            (0..20)
                .map(|k| Point::<2>::new((k / 2) as f64, (k % 2) as f64))
                .collect(),
        )
        .unwrap();
        let owner = rcb_owners(&strip, 2);
        for (i, p) in strip.positions().iter().enumerate() {
            assert_eq!(owner[i], usize::from(p[0] >= 5.0), "particle {i}");
        }
    }

    #[test]
    fn rcb_ties_are_cut_by_index() {
        // Four coincident particles in two parts: the two lowest indices form part 0.
        let set = ParticleSet::<3>::new(vec![Point::<3>::new(1.0, 1.0, 1.0); 4]).unwrap();
        assert_eq!(rcb_owners(&set, 2), vec![0, 0, 1, 1]);
        // More parts than particles: the extra parts are empty.
        assert_eq!(rcb_owners(&set, 8).len(), 4);
        let subs = rcb(&set, 8, 1.0).unwrap();
        assert_eq!(subs.iter().map(|s| s.owned.len()).sum::<usize>(), 4);
    }

    #[test]
    fn bad_owner_vectors_are_errors() {
        let set = lattice(2);
        assert!(matches!(
            with_halo(&set, &[0; 3], 2, 1.0),
            Err(CoreError::InvalidDecomposition(_))
        ));
        let mut owner = vec![0; set.len()];
        owner[5] = 2;
        let err = with_halo(&set, &owner, 2, 1.0).unwrap_err();
        assert!(err.to_string().contains("particle 5"), "{err}");
        assert!(with_halo(&set, &[0; 8], 1, -1.0).is_err());
    }

    #[test]
    fn morton_code_interleaves_bits() {
        assert_eq!(morton::<2>([0b11, 0b00]), 0b0101);
        assert_eq!(morton::<2>([0b00, 0b11]), 0b1010);
        assert_eq!(morton::<3>([1, 1, 1]), 0b111);
    }

    #[test]
    fn empty_set_gives_empty_parts() {
        let set = ParticleSet::<2>::new(Vec::new()).unwrap();
        let subs = morton_blocks(&set, 3, 1.0).unwrap();
        assert_eq!(subs.len(), 3);
        assert!(subs
            .iter()
            .all(|s| s.owned.is_empty() && s.ghosts.is_empty()));
    }
}
