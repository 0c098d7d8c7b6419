//! The particle spacing of a set, for choosing the resolution `r` when the user does not know
//! it (`boundary detect --radius auto`).

use crate::{AnyParticleSet, CoreError, NeighbourGrid, ParticleSet, Radius};

/// The median over the particles of the distance to the nearest *other* particle, ignoring
/// exact duplicates (distance 0), which say nothing about the spacing.
///
/// Returns `None` when no particle has a neighbour at a positive distance (fewer than two
/// distinct positions). Particles whose nearest neighbour is at distance `d` are found by grid
/// queries whose radius starts at the spacing a uniform filling of the bounding box would have
/// and doubles for the particles still without one, so isolated particles (droplets far from
/// the bulk) cost a few more queries, not a quadratic search. Ties in the median are no issue:
/// with an even count of distances the lower middle one is returned (a value of the data, no
/// interpolation).
///
/// ```
/// use boundary_core::{median_nearest_neighbour_distance, ParticleSet};
///
/// // A 4 x 4 lattice of spacing 0.5 plus one far particle and a duplicate.
/// let mut rows: Vec<[f64; 2]> = (0..16).map(|k| [0.5 * (k % 4) as f64, 0.5 * (k / 4) as f64]).collect();
/// rows.push([100.0, 100.0]);
/// rows.push([0.0, 0.0]);
/// let set = ParticleSet::from_rows(&rows).unwrap();
/// assert_eq!(median_nearest_neighbour_distance(&set).unwrap(), Some(0.5));
/// ```
pub fn median_nearest_neighbour_distance<const D: usize>(
    set: &ParticleSet<D>,
) -> Result<Option<f64>, CoreError> {
    let Some((lo, hi)) = set.bounding_box() else {
        return Ok(None);
    };
    let n = set.len();
    let extent = hi - lo;
    let diagonal = extent.norm();
    if diagonal == 0.0 {
        return Ok(None);
    }
    // The spacing of n particles filling the box uniformly, over the axes the set spans (a 3D
    // set in a plane spans two).
    let spanned: Vec<f64> = extent.iter().copied().filter(|&e| e > 0.0).collect();
    let volume: f64 = spanned.iter().product();
    let mut radius = (volume / n as f64)
        .powf(1.0 / spanned.len() as f64)
        .clamp(diagonal * 1e-12, diagonal);
    let mut nearest = vec![f64::INFINITY; n];
    let mut pending: Vec<usize> = (0..n).collect();
    let positions = set.positions();
    while !pending.is_empty() {
        let grid = NeighbourGrid::new(set, radius)?;
        pending.retain(|&i| {
            let mut best = f64::INFINITY;
            grid.for_each_within(&positions[i], radius, |_, d2| {
                if d2 > 0.0 && d2 < best {
                    best = d2;
                }
            });
            if best.is_finite() {
                nearest[i] = best.sqrt();
                false
            } else {
                true
            }
        });
        if radius >= diagonal {
            // Every other particle is within the diagonal: those left have only duplicates.
            break;
        }
        radius = (2.0 * radius).min(diagonal);
    }
    let mut found: Vec<f64> = nearest.into_iter().filter(|d| d.is_finite()).collect();
    if found.is_empty() {
        return Ok(None);
    }
    let middle = (found.len() - 1) / 2;
    let (_, median, _) = found.select_nth_unstable_by(middle, f64::total_cmp);
    Ok(Some(*median))
}

/// The resolution `auto` (`boundary detect --radius auto`, `detect(points, r="auto")` in
/// Python) is this multiple of the median nearest-neighbour spacing. On a lattice of spacing
/// s the sphere of an interior particle is covered for r >= s/√2 (square) or r >= s·√3/2
/// (cubic), and boundary particles stay boundary for any r; one spacing covers both lattices
/// with a margin for jitter.
pub const AUTO_RADIUS_FACTOR: f64 = 1.0;

/// The resolution estimated from the particles: [`AUTO_RADIUS_FACTOR`] times
/// [`median_nearest_neighbour_distance`]. `None` when the set has fewer than two distinct
/// positions; an error when the estimate is outside the supported radius range.
///
/// ```
/// use boundary_core::{auto_radius, AnyParticleSet, ParticleSet};
///
/// let rows: Vec<[f64; 2]> = (0..16).map(|k| [0.5 * (k % 4) as f64, 0.5 * (k / 4) as f64]).collect();
/// let set = AnyParticleSet::from(ParticleSet::from_rows(&rows).unwrap());
/// assert_eq!(auto_radius(&set).unwrap().map(|r| r.get()), Some(0.5));
/// ```
pub fn auto_radius(set: &AnyParticleSet) -> Result<Option<Radius>, CoreError> {
    let spacing = match set {
        AnyParticleSet::D2(s) => median_nearest_neighbour_distance(s),
        AnyParticleSet::D3(s) => median_nearest_neighbour_distance(s),
    }?;
    spacing
        .map(|s| Radius::new(AUTO_RADIUS_FACTOR * s))
        .transpose()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Brute force, the definition.
    fn brute<const D: usize>(set: &ParticleSet<D>) -> Option<f64> {
        let p = set.positions();
        let mut d: Vec<f64> = (0..p.len())
            .filter_map(|i| {
                (0..p.len())
                    .map(|j| (p[i] - p[j]).norm())
                    .filter(|&d| d > 0.0)
                    .min_by(f64::total_cmp)
            })
            .collect();
        if d.is_empty() {
            return None;
        }
        d.sort_by(f64::total_cmp);
        Some(d[(d.len() - 1) / 2])
    }

    #[test]
    fn agrees_with_brute_force_on_clustered_sets() {
        // Two dense clusters far apart, a line, and scattered points: the first query radius
        // is far off for most of them.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut rows = Vec::new();
        for _ in 0..150 {
            rows.push([next() * 0.01, next() * 0.01, next() * 0.01]);
            rows.push([1e3 + next(), next(), 0.0]);
        }
        for k in 0..20 {
            rows.push([f64::from(k) * 7.0, -50.0, 3.0]);
        }
        let set = ParticleSet::from_rows(&rows).unwrap();
        assert_eq!(
            median_nearest_neighbour_distance(&set).unwrap(),
            brute(&set)
        );
        let flat: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
        let set = ParticleSet::from_rows(&flat).unwrap();
        assert_eq!(
            median_nearest_neighbour_distance(&set).unwrap(),
            brute(&set)
        );
    }

    #[test]
    fn degenerate_sets_have_no_spacing() {
        let empty = ParticleSet::<3>::new(Vec::new()).unwrap();
        assert_eq!(median_nearest_neighbour_distance(&empty).unwrap(), None);
        let one = ParticleSet::from_rows(&[[1.0, 2.0]]).unwrap();
        assert_eq!(median_nearest_neighbour_distance(&one).unwrap(), None);
        let same = ParticleSet::from_rows(&[[1.0, 2.0], [1.0, 2.0]]).unwrap();
        assert_eq!(median_nearest_neighbour_distance(&same).unwrap(), None);
        // Duplicates are skipped; the pair at distance 3 is the spacing.
        let pair = ParticleSet::from_rows(&[[0.0, 0.0], [0.0, 0.0], [3.0, 0.0]]).unwrap();
        assert_eq!(median_nearest_neighbour_distance(&pair).unwrap(), Some(3.0));
    }
}
