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
        let p = set.positions();
        ParticleSet {
            positions: self
                .owned
                .iter()
                .chain(&self.ghosts)
                .map(|&i| p[i])
                .collect(),
        }
    }
}

/// Splits `order` (a permutation of the particles) into `parts` runs of nearly equal length
/// and adds to each run the ghosts within `halo`.
fn split_with_halo<const D: usize>(
    set: &ParticleSet<D>,
    order: &[usize],
    parts: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    let parts = parts.max(1);
    let n = order.len();
    let mut owner = vec![0usize; n];
    let mut subs: Vec<Subdomain> = (0..parts).map(|_| Subdomain::default()).collect();
    for (rank, chunk) in (0..parts).map(|k| (k, &order[k * n / parts..(k + 1) * n / parts])) {
        for &i in chunk {
            owner[i] = rank;
            subs[rank].owned.push(i);
        }
    }
    if n == 0 {
        return Ok(subs);
    }
    let grid = NeighbourGrid::new(set, halo)?;
    let mut mark = vec![usize::MAX; n];
    for (rank, sub) in subs.iter_mut().enumerate() {
        sub.owned.sort_unstable();
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

/// `parts` slabs along `axis`, balanced by count (particles sorted by that coordinate, ties
/// by index), each with its ghosts within `halo`.
pub fn slabs<const D: usize>(
    set: &ParticleSet<D>,
    parts: usize,
    axis: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    let axis = axis.min(D - 1);
    let p = set.positions();
    let mut order: Vec<usize> = (0..set.len()).collect();
    order.sort_by(|&a, &b| p[a][axis].total_cmp(&p[b][axis]).then(a.cmp(&b)));
    split_with_halo(set, &order, parts, halo)
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

/// `parts` blocks of consecutive particles in Morton order of their cells (side `halo`),
/// balanced by count, each with its ghosts within `halo`.
pub fn morton_blocks<const D: usize>(
    set: &ParticleSet<D>,
    parts: usize,
    halo: f64,
) -> Result<Vec<Subdomain>, CoreError> {
    let Some((lo, _)) = set.bounding_box() else {
        return split_with_halo(set, &[], parts, halo);
    };
    let cell = |p: &Point<D>| -> [u64; D] {
        std::array::from_fn(|k| ((p[k] - lo[k]) / halo).floor().clamp(0.0, 2e6) as u64)
    };
    let p = set.positions();
    let mut keyed: Vec<(u64, usize)> = (0..set.len()).map(|i| (morton(cell(&p[i])), i)).collect();
    keyed.sort_unstable();
    let order: Vec<usize> = keyed.into_iter().map(|(_, i)| i).collect();
    split_with_halo(set, &order, parts, halo)
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
        }
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
