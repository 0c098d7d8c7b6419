//! Where the approximate methods fail: every miss of a method without a certificate
//! (`BoundaryDetector::certified()` false) placed by the shape of the fluid around it, and
//! each such method's worst scene kept for a picture.
//!
//! Classes, computed from the exact labels of the scene at run time:
//! - a **false negative** (an exact boundary particle called interior) takes the feature of the
//!   exact boundary at that particle, from [`boundary_resample::classify`] at its defaults
//!   (thesis Sec. 2.6, Eq. 2.4–2.5, neighbourhood 2r): *droplet* (fewer than 4 particles within
//!   2r, itself included), *filament* (the thesis' ligament: one dominant direction), *sheet*
//!   (one thin direction; 3D only), or *surface* (a regular boundary particle);
//! - a **false positive** (an exact interior particle called boundary) takes its distance d to
//!   the nearest exact boundary particle: d <= r (touching the surface layer), r < d <= 2r
//!   (the next layers), or deeper (d > 2r, or no boundary particle at all): the deep ones are
//!   where a method sees a surface that is not there (a false cavity, a density dip);
//! - an exact interior particle is also counted as **sparse** when it has fewer than 3/4 of the
//!   median neighbour count (particles within 2r, itself included) of the scene's interior
//!   particles: the thinned regions of a stretched flow.
//!
//! The worst scene of a method is the one of lowest M at default parameters (the first one in
//! scene order on ties); its picture is drawn by [`crate::plots`].

use crate::Row;
use boundary::implement::NeighbourGrid;
use boundary::{AnyParticleSet, Labels, ParticleSet, Radius};
use boundary::{Dim, SupportedDim};
use rayon::prelude::*;
use std::fmt::Write as _;

/// Names of the false-negative classes, in [`MissProfile::boundary`] order.
pub const FN_CLASSES: [&str; 4] = ["droplet", "filament", "sheet", "surface"];

/// Names of the false-positive classes, in [`MissProfile::interior`] order.
pub const FP_CLASSES: [&str; 3] = ["d <= r", "r < d <= 2r", "d > 2r"];

/// Class of each particle of a scene: `0..4` an exact boundary particle of class
/// [`FN_CLASSES`]`[c]`, `4..7` an exact interior particle of class [`FP_CLASSES`]`[c - 4]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneClasses {
    /// One class per particle.
    pub class: Vec<u8>,
    /// Per particle: an exact interior particle in a sparse region (see the module docs).
    pub sparse: Vec<bool>,
}

/// How many particles of each class a scene has and how many of them a method got wrong.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MissProfile {
    /// Exact boundary particles per [`FN_CLASSES`] class.
    pub boundary: [usize; 4],
    /// Of those, the ones called interior (false negatives).
    pub fn_: [usize; 4],
    /// Exact interior particles per [`FP_CLASSES`] class.
    pub interior: [usize; 3],
    /// Of those, the ones called boundary (false positives).
    pub fp: [usize; 3],
    /// Exact interior particles in sparse regions.
    pub sparse_interior: usize,
    /// Of those, the ones called boundary.
    pub sparse_fp: usize,
}

impl MissProfile {
    /// Counts a method's misses by class. `labels`, `truth` and `classes` must have the same
    /// length (they come from one scene).
    pub fn of(classes: &SceneClasses, labels: &Labels, truth: &Labels) -> Result<Self, String> {
        let n = classes.class.len();
        if labels.len() != n || truth.len() != n || classes.sparse.len() != n {
            return Err(format!(
                "{} labels and {} exact labels for {n} classified particles",
                labels.len(),
                truth.len()
            ));
        }
        let mut p = MissProfile::default();
        for (i, &c) in classes.class.iter().enumerate() {
            let c = c as usize;
            let said = labels.is_boundary(i);
            if truth.is_boundary(i) {
                let c = c.min(3);
                p.boundary[c] += 1;
                p.fn_[c] += usize::from(!said);
            } else {
                let c = c.saturating_sub(4).min(2);
                p.interior[c] += 1;
                p.fp[c] += usize::from(said);
                if classes.sparse[i] {
                    p.sparse_interior += 1;
                    p.sparse_fp += usize::from(said);
                }
            }
        }
        Ok(p)
    }

    /// Sums two profiles (pooling over scenes).
    pub fn add(&mut self, other: &MissProfile) {
        for k in 0..4 {
            self.boundary[k] += other.boundary[k];
            self.fn_[k] += other.fn_[k];
        }
        for k in 0..3 {
            self.interior[k] += other.interior[k];
            self.fp[k] += other.fp[k];
        }
        self.sparse_interior += other.sparse_interior;
        self.sparse_fp += other.sparse_fp;
    }
}

/// Classes of every particle of a scene from its exact labels (see the module docs).
pub fn scene_classes(
    set: &AnyParticleSet,
    r: Radius,
    truth: &Labels,
) -> Result<SceneClasses, String> {
    match set {
        AnyParticleSet::D2(s) => classes_d(s, r, truth),
        AnyParticleSet::D3(s) => classes_d(s, r, truth),
    }
}

fn classes_d<const D: usize>(
    set: &ParticleSet<D>,
    r: Radius,
    truth: &Labels,
) -> Result<SceneClasses, String>
where
    Dim<D>: SupportedDim,
{
    let features =
        boundary_resample::classify(set, r, truth, &boundary_resample::ResampleConfig::default())
            .map_err(|e| e.to_string())?;
    let pos = set.positions();
    let surface: Vec<_> = (0..set.len())
        .filter(|&i| truth.is_boundary(i))
        .map(|i| pos[i])
        .collect();
    let (near, far) = (r.get(), 2.0 * r.get());
    let grid = if surface.is_empty() {
        None
    } else {
        let surface = ParticleSet::new(surface).map_err(|e| e.to_string())?;
        let grid = NeighbourGrid::new(&surface, far).map_err(|e| e.to_string())?;
        Some(grid)
    };
    let class = features
        .par_iter()
        .enumerate()
        .map(|(i, f)| match f.feature {
            Some(feature) => match feature {
                boundary_resample::Feature::Droplet => 0,
                boundary_resample::Feature::Ligament => 1,
                boundary_resample::Feature::Sheet => 2,
                boundary_resample::Feature::Regular => 3,
            },
            None => {
                let mut d2 = f64::INFINITY;
                if let Some(grid) = &grid {
                    grid.for_each_within(&pos[i], far, |_, e2| d2 = d2.min(e2));
                }
                if d2 <= near * near {
                    4
                } else if d2 <= far * far {
                    5
                } else {
                    6
                }
            }
        })
        .collect();
    // Neighbour counts of the interior particles, and their median.
    let all = NeighbourGrid::new(set, far).map_err(|e| e.to_string())?;
    let counts: Vec<usize> = (0..set.len())
        .into_par_iter()
        .map(|i| {
            let mut k = 0;
            if !truth.is_boundary(i) {
                all.for_each_within(&pos[i], far, |_, _| k += 1);
            }
            k
        })
        .collect();
    let mut interior: Vec<usize> = (0..set.len())
        .filter(|&i| !truth.is_boundary(i))
        .map(|i| counts[i])
        .collect();
    interior.sort_unstable();
    let median = interior.get(interior.len() / 2).copied().unwrap_or(0);
    let sparse = (0..set.len())
        .map(|i| !truth.is_boundary(i) && 4 * counts[i] < 3 * median)
        .collect();
    Ok(SceneClasses { class, sparse })
}

/// One approximate method's worst scene, with what is needed to draw its misses.
#[derive(Debug, Clone)]
pub struct FailurePicture {
    /// Method name.
    pub method: String,
    /// Scene name.
    pub scene: String,
    /// Dimension (2 or 3).
    pub dim: usize,
    /// The scene's resolution r.
    pub radius: f64,
    /// Positions, `dim` coordinates per particle.
    pub coords: Vec<f64>,
    /// Exact labels.
    pub truth: Labels,
    /// The method's labels at default parameters.
    pub labels: Labels,
    /// The method's M on this scene.
    pub m: f64,
}

impl FailurePicture {
    /// Position of particle `i` (`dim` coordinates).
    pub fn point(&self, i: usize) -> &[f64] {
        &self.coords[i * self.dim..(i + 1) * self.dim]
    }

    /// Indices of the particles the method got wrong.
    pub fn misses(&self) -> Vec<usize> {
        (0..self.truth.len())
            .filter(|&i| self.labels.is_boundary(i) != self.truth.is_boundary(i))
            .collect()
    }

    /// The slab of a 3D scene to draw: `(axis, lo, hi)` of thickness `2r` along the axis that,
    /// of all slabs of that thickness on the three axes, holds the most misses (the first axis
    /// and lowest position on ties); `None` in 2D or when there is no miss.
    pub fn slab(&self) -> Option<(usize, f64, f64)> {
        if self.dim != 3 {
            return None;
        }
        let misses = self.misses();
        let width = 2.0 * self.radius;
        let mut best: Option<(usize, usize, f64)> = None;
        for axis in 0..3 {
            let mut xs: Vec<f64> = misses.iter().map(|&i| self.point(i)[axis]).collect();
            xs.sort_by(f64::total_cmp);
            let mut hi = 0;
            for lo in 0..xs.len() {
                while hi < xs.len() && xs[hi] <= xs[lo] + width {
                    hi += 1;
                }
                if best.is_none_or(|b| hi - lo > b.1) {
                    best = Some((axis, hi - lo, xs[lo]));
                }
            }
        }
        best.map(|(axis, _, lo)| (axis, lo, lo + width))
    }
}

/// The approximate methods of the rows (default rows with `certified` false), in row order.
pub fn approximate_methods(rows: &[Row]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for row in rows.iter().filter(|r| r.is_default && !r.certified) {
        if !names.contains(&row.method) {
            names.push(row.method.clone());
        }
    }
    names
}

/// The default-parameter rows of `method` that have a score, worst M first (scene order on
/// ties).
pub fn ranked<'a>(rows: &'a [Row], method: &str) -> Vec<&'a Row> {
    let mut sel: Vec<&Row> = rows
        .iter()
        .filter(|r| r.method == method && r.is_default && r.confusion.is_some())
        .collect();
    sel.sort_by(|a, b| m_of(a).total_cmp(&m_of(b)));
    sel
}

fn m_of(row: &Row) -> f64 {
    row.confusion.map_or(f64::NAN, |c| c.m())
}

fn share(part: usize, whole: usize) -> String {
    if whole == 0 {
        "-".into()
    } else {
        format!("{part}/{whole}")
    }
}

fn percent(part: usize, whole: usize) -> f64 {
    100.0 * part as f64 / whole.max(1) as f64
}

/// The class with the most misses (the first on ties) and its count; `None` without misses.
fn largest(counts: &[usize]) -> Option<usize> {
    let (k, &c) = counts
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(&a.0)))?;
    (c > 0).then_some(k)
}

/// How many worst scenes the table of each method lists.
pub const WORST_SCENES: usize = 3;

/// The report section "Where the approximate methods fail". `about` gives a short description
/// of each scene (its generator and parameters, or its provenance); `pictures` the picture
/// files written for each method (relative to the report).
pub fn section_md(
    rows: &[Row],
    about: &[(String, String)],
    pictures: &[(String, String)],
) -> String {
    let mut md = String::new();
    let methods = approximate_methods(rows);
    if methods.is_empty() {
        return md;
    }
    let _ = writeln!(md, "## Where the approximate methods fail\n");
    let _ = writeln!(
        md,
        "Methods without a certificate at default parameters: {}. A false negative (FN) is \
         classed by the exact boundary's feature at the particle (thesis Sec. 2.6: droplet, \
         filament, sheet, surface), a false positive (FP) by its distance d to the nearest \
         exact boundary particle. Cells are missed/present particles of the class; the worst \
         scenes are those of lowest M.\n",
        methods
            .iter()
            .map(|m| format!("`{m}`"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for method in &methods {
        let _ = writeln!(md, "### `{method}`\n");
        let ranked = ranked(rows, method);
        let mut pooled = MissProfile::default();
        for row in &ranked {
            if let Some(p) = &row.misses {
                pooled.add(p);
            }
        }
        let fn_total: usize = pooled.fn_.iter().sum();
        let fp_total: usize = pooled.fp.iter().sum();
        let _ = writeln!(
            md,
            "Pooled over {} scenes: {fn_total} FN, {fp_total} FP.",
            ranked.len()
        );
        if let Some(k) = largest(&pooled.fn_) {
            let _ = write!(
                md,
                "Most false negatives are {} particles ({:.0}% of the FN). ",
                FN_CLASSES[k],
                percent(pooled.fn_[k], fn_total),
            );
            let _ = writeln!(
                md,
                "Missed per class: {}.",
                (0..4)
                    .filter(|&c| pooled.boundary[c] > 0)
                    .map(|c| format!(
                        "{} {:.1}% of {}",
                        FN_CLASSES[c],
                        percent(pooled.fn_[c], pooled.boundary[c]),
                        pooled.boundary[c]
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        if let Some(k) = largest(&pooled.fp) {
            let _ = writeln!(
                md,
                "Most false positives lie at {} ({:.0}% of the FP; {:.2}% of the interior \
                 particles there).",
                FP_CLASSES[k],
                percent(pooled.fp[k], fp_total),
                percent(pooled.fp[k], pooled.interior[k]),
            );
            let interior_total: usize = pooled.interior.iter().sum();
            let _ = writeln!(
                md,
                "{} FP ({:.0}%) lie in sparse regions (fewer than 3/4 of the median interior \
                 neighbour count), which hold {:.1}% of the interior particles.",
                pooled.sparse_fp,
                percent(pooled.sparse_fp, fp_total),
                percent(pooled.sparse_interior, interior_total),
            );
        }
        if fn_total + fp_total == 0 {
            let _ = writeln!(md, "No miss on any scene.");
        }
        md.push('\n');
        let _ = writeln!(
            md,
            "| Scene | M | FN | FP | FN {} | FP {} | FP sparse | scene |\n|---|---|---|---|{}{}---|---|",
            FN_CLASSES.join(" | FN "),
            FP_CLASSES.join(" | FP "),
            "---|".repeat(FN_CLASSES.len()),
            "---|".repeat(FP_CLASSES.len()),
        );
        for row in ranked.iter().take(WORST_SCENES) {
            let Some(c) = row.confusion else { continue };
            let p = row.misses.unwrap_or_default();
            let fns: Vec<String> = (0..4).map(|k| share(p.fn_[k], p.boundary[k])).collect();
            let fps: Vec<String> = (0..3).map(|k| share(p.fp[k], p.interior[k])).collect();
            let what = about
                .iter()
                .find(|a| a.0 == row.scene)
                .map_or("", |a| a.1.as_str());
            let _ = writeln!(
                md,
                "| `{}` ({}D) | {:.4} | {} | {} | {} | {} | {} | {} |",
                row.scene,
                row.dim,
                c.m(),
                c.fn_,
                c.fp,
                fns.join(" | "),
                fps.join(" | "),
                share(p.sparse_fp, p.sparse_interior),
                what.replace('|', "/"),
            );
        }
        if let Some((_, file)) = pictures.iter().find(|p| &p.0 == method) {
            let _ = writeln!(
                md,
                "\nPicture of the worst scene: [`{file}`]({file}) (false negatives blue, false \
                 positives red; a 3D scene is cut to the 2r-thick slab holding the most misses, \
                 beside a projection of all misses)."
            );
        }
        md.push('\n');
    }
    md
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
    use super::*;
    use boundary::{detector_by_name, Confusion};

    /// A dense block (spacing 1) beside a stretched one (spacing 1.6 in x), a filament of 10
    /// particles 0.5 apart and a lone droplet, at r = 1.2.
    fn scene() -> (AnyParticleSet, Radius, usize, std::ops::Range<usize>) {
        let mut rows = Vec::new();
        for j in 0..10 {
            for i in 0..10 {
                rows.push([i as f64, j as f64]);
            }
            for i in 1..=6 {
                rows.push([9.0 + 1.6 * i as f64, j as f64]);
            }
        }
        let filament = rows.len()..rows.len() + 10;
        for k in 0..10 {
            rows.push([0.5 * k as f64, 40.0]);
        }
        let droplet = rows.len();
        rows.push([60.0, 60.0]);
        let set = AnyParticleSet::D2(ParticleSet::from_rows(&rows).unwrap());
        (set, Radius::new(1.2).unwrap(), droplet, filament)
    }

    #[test]
    fn classes_put_droplets_filaments_and_interior_depths_where_a_brute_force_check_does() {
        let (set, r, droplet, filament) = scene();
        let truth = detector_by_name("exact")
            .unwrap()
            .detect(&set, r)
            .unwrap()
            .labels;
        let classes = scene_classes(&set, r, &truth).unwrap();
        assert_eq!(classes.class[droplet], 0);
        assert!(filament.clone().all(|i| classes.class[i] == 1));
        // Depth and sparsity of the interior particles, by brute force.
        let n = set.len();
        let d2 = |i: usize, j: usize| -> f64 {
            let (a, b) = (set.coords(i), set.coords(j));
            (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
        };
        let rr = r.get();
        let count = |i: usize| (0..n).filter(|&j| d2(i, j) <= 4.0 * rr * rr).count();
        let mut counts: Vec<usize> = (0..n)
            .filter(|&i| !truth.is_boundary(i))
            .map(count)
            .collect();
        counts.sort_unstable();
        let median = counts[counts.len() / 2];
        let mut seen = [0usize; 3];
        let mut sparse = 0;
        for i in (0..n).filter(|&i| !truth.is_boundary(i)) {
            let d = (0..n)
                .filter(|&j| truth.is_boundary(j))
                .map(|j| d2(i, j).sqrt())
                .fold(f64::INFINITY, f64::min);
            let want = if d <= rr {
                4
            } else if d <= 2.0 * rr {
                5
            } else {
                6
            };
            assert_eq!(classes.class[i], want, "particle {i} at depth {d}");
            seen[want as usize - 4] += 1;
            assert_eq!(classes.sparse[i], 4 * count(i) < 3 * median, "particle {i}");
            sparse += usize::from(classes.sparse[i]);
        }
        // The scene exercises every depth class, and the stretched block is sparse.
        assert!(seen.iter().all(|&k| k > 0), "{seen:?}");
        assert!(
            sparse > 0 && sparse < counts.len(),
            "{sparse} of {}",
            counts.len()
        );
    }

    #[test]
    fn miss_profile_counts_each_flipped_label_in_its_class() {
        let (set, r, droplet, filament) = scene();
        let truth = detector_by_name("exact")
            .unwrap()
            .detect(&set, r)
            .unwrap()
            .labels;
        let classes = scene_classes(&set, r, &truth).unwrap();
        let deep = (0..set.len()).find(|&i| classes.class[i] == 6).unwrap();
        let sparse = (0..set.len()).find(|&i| classes.sparse[i]).unwrap();
        let mut said = truth.as_slice().to_vec();
        for i in [droplet, filament.start, deep, sparse] {
            said[i] = !said[i];
        }
        let labels = Labels::new(said);
        let p = MissProfile::of(&classes, &labels, &truth).unwrap();
        assert_eq!(p.fn_, [1, 1, 0, 0]);
        assert_eq!(p.fp[2], 1);
        assert_eq!(p.fp.iter().sum::<usize>(), 2);
        assert_eq!(p.sparse_fp, 1);
        assert_eq!(p.boundary.iter().sum::<usize>(), truth.boundary_count());
        assert_eq!(
            p.interior.iter().sum::<usize>(),
            set.len() - truth.boundary_count()
        );
        let c = Confusion::from_labels(labels.as_slice(), truth.as_slice()).unwrap();
        assert_eq!((c.fn_, c.fp), (2, 2));
        // Labels of another scene are an error, not a panic.
        let short = Labels::new(vec![true; 3]);
        assert!(MissProfile::of(&classes, &short, &truth).is_err());
    }

    fn row(scene: &str, method: &str, certified: bool, fn_: usize, fp: usize) -> Row {
        Row {
            scene: scene.into(),
            dim: 3,
            n: 100,
            radius: 0.1,
            method: method.into(),
            params: String::new(),
            is_default: true,
            certified,
            misses: Some(MissProfile {
                boundary: [2, 3, 0, 45],
                fn_: [0, fn_.min(3), 0, fn_.saturating_sub(3)],
                interior: [20, 20, 10],
                fp: [fp, 0, 0],
                sparse_interior: 5,
                sparse_fp: fp.min(5),
            }),
            confusion: Some(Confusion {
                tp: 50 - fn_ as u64,
                fn_: fn_ as u64,
                fp: fp as u64,
                tn: 50 - fp as u64,
            }),
            seconds_1: None,
            seconds_all: 0.1,
            threads: 1,
            error: None,
            unsupported: false,
            interface: None,
            interface_confusion: None,
        }
    }

    #[test]
    fn section_lists_each_approximate_method_with_its_worst_scene_by_m_first() {
        let mut rows = Vec::new();
        for scene in ["a", "b", "c", "d"] {
            rows.push(row(scene, "exact", true, 0, 0));
        }
        // hpr: worst on c (M 0.8 · 0.96 = 0.768); svm: b and d tie at the lowest M, b comes first.
        for (scene, f, p) in [("a", 1, 0), ("b", 2, 1), ("c", 10, 2), ("d", 0, 0)] {
            rows.push(row(scene, "hpr", false, f, p));
        }
        for (scene, f, p) in [("a", 0, 1), ("b", 5, 0), ("c", 0, 0), ("d", 5, 0)] {
            rows.push(row(scene, "svm", false, f, p));
        }
        assert_eq!(approximate_methods(&rows), ["hpr", "svm"]);
        let worst: Vec<&str> = ranked(&rows, "hpr")
            .iter()
            .map(|r| r.scene.as_str())
            .collect();
        assert_eq!(worst, ["c", "b", "a", "d"]);
        assert_eq!(ranked(&rows, "svm")[0].scene, "b");
        let about = vec![("c".to_string(), "a stretched sheet".to_string())];
        let pictures = vec![("hpr".to_string(), "fail_hpr.png".to_string())];
        let md = section_md(&rows, &about, &pictures);
        assert!(md.contains("### `hpr`") && md.contains("### `svm`"), "{md}");
        assert!(!md.contains("### `exact`"), "{md}");
        let hpr = &md[md.find("### `hpr`").unwrap()..md.find("### `svm`").unwrap()];
        let first = hpr.lines().find(|l| l.starts_with("| `")).unwrap();
        assert!(
            first.starts_with("| `c` (3D) | 0.7680 | 10 | 2 |"),
            "{first}"
        );
        assert!(first.ends_with("| 2/5 | a stretched sheet |"), "{first}");
        assert_eq!(
            hpr.lines().filter(|l| l.starts_with("| `")).count(),
            WORST_SCENES
        );
        assert!(hpr.contains("[`fail_hpr.png`](fail_hpr.png)"));
        // Pooled over hpr's scenes: 13 FN, 7 of them surface ones, 6 filament ones.
        assert!(hpr.contains("13 FN, 3 FP"), "{hpr}");
        assert!(hpr.contains("Most false negatives are surface particles (54% of the FN)"));
        let svm = &md[md.find("### `svm`").unwrap()..];
        let first = svm.lines().find(|l| l.starts_with("| `")).unwrap();
        assert!(first.starts_with("| `b` (3D) |"), "{first}");
        assert!(!svm.contains("Picture of the worst scene"));
        // No approximate method, no section.
        assert!(section_md(&rows[..4], &about, &pictures).is_empty());
    }

    fn lattice_picture() -> FailurePicture {
        let mut coords = Vec::new();
        let mut said = Vec::new();
        for z in 0..8 {
            for y in 0..8 {
                for x in 0..8 {
                    coords.extend([x as f64, y as f64, z as f64]);
                    // The plane z = 5 is all wrong, and three particles of the plane x = 1.
                    said.push(z == 5 || (x == 1 && y < 3 && z == 0));
                }
            }
        }
        FailurePicture {
            method: "hpr".into(),
            scene: "lattice".into(),
            dim: 3,
            radius: 0.9,
            coords,
            truth: Labels::new(vec![false; 512]),
            labels: Labels::new(said),
            m: 0.5,
        }
    }

    #[test]
    fn slab_holds_the_most_misses_of_any_2r_slab() {
        let pic = lattice_picture();
        let (axis, lo, hi) = pic.slab().unwrap();
        assert_eq!((axis, lo), (2, 5.0));
        assert!((hi - lo - 1.8).abs() < 1e-12);
        let misses = pic.misses();
        let inside = |a: usize, lo: f64| {
            misses
                .iter()
                .filter(|&&i| (lo..=lo + 1.8).contains(&pic.point(i)[a]))
                .count()
        };
        let best = inside(axis, lo);
        for a in 0..3 {
            for &i in &misses {
                assert!(inside(a, pic.point(i)[a]) <= best);
            }
        }
        let mut flat = pic.clone();
        flat.dim = 2;
        flat.coords = (0..512).flat_map(|i| [i as f64, 0.0]).collect();
        assert_eq!(flat.slab(), None);
    }
}
