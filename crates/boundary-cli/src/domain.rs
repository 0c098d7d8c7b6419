//! `detect`'s simulation options: wall particles (`--walls`, `--wall-attribute`,
//! `--wall-array`), solid
//! half-spaces (`--solid`), periodic axes (`--periodic`) and phases (`--phase-attribute`),
//! turned into the core's [`Domain`] once per frame. The definition lives in the core
//! (`boundary::domain`); this module only reads files and attributes.

use crate::common::{attach_radii, point_attribute, InputArgs, RadiusMode};
use crate::error::CliError;
use boundary::{
    AnyParticleSet, CoreError, Domain, HalfSpace, ParticleSet, Periodic, Point, SolidMesh,
};
use boundary::{Dim, SupportedDim};
use boundary_io::{read_frame, read_mesh, AttributeValues, Format, Frame, FrameParts, ReadOptions};
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::Arc;

#[derive(Debug, Args)]
pub(crate) struct DomainArgs {
    /// Wall particles from FILE (repeatable, files joined; any input format): they cover the
    /// particles of INPUT and get no label; the output holds INPUT's particles only. With
    /// --radius-attribute NAME, a wall file with that attribute gives its walls their radii
    /// (else radius factor 1).
    #[arg(long = "walls", value_name = "FILE")]
    pub(crate) walls: Vec<PathBuf>,
    /// Wall particles of INPUT itself: the rows whose point attribute NAME has one of the
    /// values V (e.g. `type=0,1`). They cover and get no label: every row is written back,
    /// with a `wall` column (1 for a wall row) and `boundary` = 0 (margin NaN) for wall rows;
    /// the summary counts the other particles only.
    #[arg(long, value_name = "NAME=V[,V...]", value_parser = parse_wall_attribute)]
    pub(crate) wall_attribute: Option<WallSelector>,
    /// Wall particles from the particle array NAME of INPUT itself (repeatable): PySPH's
    /// .hdf5 and .npz hold each array (`fluid`, `boundary`, `solid`, …) in one file, and INPUT is its
    /// `fluid` array. Read from every frame, so moving walls move; like --walls they cover
    /// and get no label.
    #[arg(long = "wall-array", value_name = "NAME")]
    pub(crate) wall_arrays: Vec<String>,
    /// A closed solid half-space that covers like the particles do (repeatable): an axis,
    /// `<` or `>`, a bound, e.g. 'y<0' (quoted) for a floor at y = 0. Not every method can
    /// honour it; those that cannot say so.
    #[arg(long = "solid", value_name = "AXIS<V|AXIS>V", value_parser = parse_solid)]
    pub(crate) solids: Vec<HalfSpace>,
    /// The inside of a closed triangle mesh (STL, OBJ or PLY; repeatable) is solid, like
    /// --solid (3D only; its surface counts as solid). Honoured by `exact` (a witness search
    /// with a stated tolerance, see its docs); the other methods refuse it.
    #[arg(long = "solid-mesh", value_name = "FILE")]
    pub(crate) solid_meshes: Vec<PathBuf>,
    /// A periodic axis (repeatable, one per axis): particles leaving MAX re-enter at MIN,
    /// e.g. `x:0:1.5`. Every particle must lie in [MIN, MAX].
    #[arg(long = "periodic", value_name = "AXIS:MIN:MAX", value_parser = parse_periodic)]
    pub(crate) periodic: Vec<Periodic>,
    /// Phase numbers (integers >= 0) from the point attribute NAME: adds an `interface`
    /// column (1 for a particle on the interface between phases, not on the free surface);
    /// `boundary` stays the free surface.
    #[arg(long, value_name = "NAME")]
    pub(crate) phase_attribute: Option<String>,
}

impl DomainArgs {
    /// Whether the options read point attributes of each frame (`--wall-attribute`,
    /// `--phase-attribute`).
    pub(crate) fn reads_attributes(&self) -> bool {
        self.wall_attribute.is_some() || self.phase_attribute.is_some()
    }
}

/// `--wall-attribute NAME=V[,V...]`: the attribute and the values that mark a wall row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WallSelector {
    name: String,
    values: Vec<f64>,
}

impl WallSelector {
    /// `NAME=V[,V...]` as given.
    fn describe(&self) -> String {
        let values: Vec<String> = self.values.iter().map(f64::to_string).collect();
        format!("{}={}", self.name, values.join(","))
    }
}

fn parse_wall_attribute(text: &str) -> Result<WallSelector, String> {
    let (name, list) = text
        .split_once('=')
        .ok_or_else(|| format!("'{text}': expected NAME=V[,V...], e.g. 'type=0,1'"))?;
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("'{text}': the attribute name is empty"));
    }
    let values = list
        .split(',')
        .map(|v| {
            let v = v.trim();
            match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ if v.is_empty() => Err(format!("'{text}': an empty value in the list")),
                _ => Err(format!("'{text}': '{v}' is not a finite number")),
            }
        })
        .collect::<Result<Vec<f64>, String>>()?;
    Ok(WallSelector {
        name: name.to_owned(),
        values,
    })
}

fn parse_solid(text: &str) -> Result<HalfSpace, String> {
    HalfSpace::parse(text).map_err(|e| e.to_string())
}

fn parse_periodic(text: &str) -> Result<Periodic, String> {
    Periodic::parse(text).map_err(|e| e.to_string())
}

/// What every frame of a run shares: the walls of the `--walls` files (read once), the
/// solids, the periodic axes and the attributes to read from each frame.
#[derive(Debug)]
pub(crate) struct DomainSetup {
    /// The `--walls` files joined, and the first file (named in messages).
    file_walls: Option<(AnyParticleSet, PathBuf)>,
    /// `--wall-array`: particle arrays of each input file that are walls.
    wall_arrays: Vec<String>,
    /// The run's resolution, for the radii of the wall arrays.
    mode: RadiusMode,
    /// How the inputs are read (`--dim`, `--format`), for their wall arrays.
    input_dim: Option<usize>,
    input_format: Option<Format>,
    selector: Option<WallSelector>,
    solids: Vec<HalfSpace>,
    /// The `--solid-mesh` files, read and validated once, with their paths.
    meshes: Vec<(Arc<SolidMesh>, PathBuf)>,
    periodic: Vec<Periodic>,
    phase_attribute: Option<String>,
}

/// One frame in its domain.
#[derive(Debug)]
pub(crate) struct FrameDomain {
    /// The classified particles when some rows of the input are walls (`--wall-attribute`);
    /// `None`: every row is classified.
    fluid: Option<AnyParticleSet>,
    /// The input rows of the classified particles, with `fluid`.
    rows: Option<Vec<usize>>,
    /// Per input row, whether it is a wall (`--wall-attribute` only).
    pub(crate) wall_rows: Option<Vec<bool>>,
    pub(crate) domain: Domain,
    /// The wall particles used, from the files and from the input.
    pub(crate) walls: usize,
}

impl FrameDomain {
    /// The classified particles; `all` is the input's set.
    pub(crate) fn fluid<'a>(&'a self, all: &'a AnyParticleSet) -> &'a AnyParticleSet {
        self.fluid.as_ref().unwrap_or(all)
    }

    /// Values of the classified particles placed at their input rows, `fill` at wall rows.
    pub(crate) fn scatter<T: Copy>(&self, rows: usize, values: &[T], fill: T) -> Vec<T> {
        match &self.rows {
            None => values.to_vec(),
            Some(at) => {
                let mut out = vec![fill; rows];
                for (&i, &v) in at.iter().zip(values) {
                    out[i] = v;
                }
                out
            }
        }
    }
}

impl DomainSetup {
    /// The setup the options ask for, reading the `--walls` files; `None` when no option is
    /// given (the bare cloud: `detect` runs as without this module).
    pub(crate) fn new(
        args: &DomainArgs,
        input: &InputArgs,
        mode: &RadiusMode,
    ) -> Result<Option<Self>, CliError> {
        let bare = args.walls.is_empty()
            && args.wall_attribute.is_none()
            && args.wall_arrays.is_empty()
            && args.solids.is_empty()
            && args.solid_meshes.is_empty()
            && args.periodic.is_empty()
            && args.phase_attribute.is_none();
        if bare {
            return Ok(None);
        }
        let mut sets: Vec<AnyParticleSet> = Vec::new();
        for path in &args.walls {
            let options = ReadOptions {
                dim: input.dim.map(usize::from),
                format: Format::from_path(path).or(input.format),
            };
            let set = read_walls(path, None, &options, mode)?;
            if let Some(first) = sets.first() {
                if first.dim() != set.dim() {
                    return Err(CliError::WallFile {
                        path: path.clone(),
                        problem: format!(
                            "{}D particles, but {} holds {}D particles",
                            set.dim(),
                            args.walls[0].display(),
                            first.dim()
                        ),
                    });
                }
            }
            sets.push(set);
        }
        let file_walls = match sets.len() {
            0 => None,
            1 => sets.pop().map(|s| (s, args.walls[0].clone())),
            _ => {
                let parts: Vec<&AnyParticleSet> = sets.iter().collect();
                Some((join_any(&parts)?, args.walls[0].clone()))
            }
        };
        let mut meshes = Vec::new();
        for path in &args.solid_meshes {
            let (vertices, triangles) = read_mesh(path)?;
            let mesh = SolidMesh::new(vertices, triangles).map_err(|e| CliError::SolidMesh {
                path: path.clone(),
                problem: e.to_string(),
            })?;
            meshes.push((Arc::new(mesh), path.clone()));
        }
        Ok(Some(DomainSetup {
            file_walls,
            wall_arrays: args.wall_arrays.clone(),
            mode: mode.clone(),
            input_dim: input.dim.map(usize::from),
            input_format: input.format,
            selector: args.wall_attribute.clone(),
            solids: args.solids.clone(),
            meshes,
            periodic: args.periodic.clone(),
            phase_attribute: args.phase_attribute.clone(),
        }))
    }

    /// Whether wall particles were asked for (`--walls`, `--wall-attribute`, `--wall-array`).
    pub(crate) fn has_walls(&self) -> bool {
        self.file_walls.is_some() || self.selector.is_some() || !self.wall_arrays.is_empty()
    }

    /// Whether the detection reports interfaces.
    pub(crate) fn has_phases(&self) -> bool {
        self.phase_attribute.is_some()
    }

    /// The solids as given (`y<0`).
    pub(crate) fn solids(&self) -> Vec<String> {
        self.solids.iter().map(ToString::to_string).collect()
    }

    /// The `--solid-mesh` files as given.
    pub(crate) fn solid_meshes(&self) -> Vec<String> {
        self.meshes
            .iter()
            .map(|(_, p)| p.display().to_string())
            .collect()
    }

    /// The periodic axes as given (`x:0:1`).
    pub(crate) fn periodic(&self) -> Vec<String> {
        self.periodic.iter().map(ToString::to_string).collect()
    }

    /// The `--wall-array` names as given.
    pub(crate) fn wall_arrays(&self) -> &[String] {
        &self.wall_arrays
    }

    /// `--wall-attribute` as given.
    pub(crate) fn wall_attribute(&self) -> Option<String> {
        self.selector.as_ref().map(WallSelector::describe)
    }

    /// The domain of `frame` (with its radii attached, if any).
    pub(crate) fn frame_domain(&self, frame: &Frame) -> Result<FrameDomain, CliError> {
        let set = &frame.set;
        let input = frame.path.as_path();
        if let Some((walls, path)) = &self.file_walls {
            if walls.dim() != set.dim() {
                return Err(CliError::WallDimension {
                    wall: path.clone(),
                    wall_dim: walls.dim(),
                    input: input.to_path_buf(),
                    dim: set.dim(),
                });
            }
        }
        // Wall rows of the input itself.
        let (fluid, rows, wall_rows, input_walls) = match &self.selector {
            None => (None, None, None, None),
            Some(selector) => {
                let attribute =
                    point_attribute(frame, &selector.name, "--wall-attribute", "a wall flag")?;
                let is_wall = |x: f64| selector.values.contains(&x);
                let mask: Vec<bool> = match &attribute.values {
                    AttributeValues::Int(v) => v.iter().map(|&i| is_wall(i as f64)).collect(),
                    AttributeValues::Float(v) => v.iter().map(|&x| is_wall(x)).collect(),
                };
                let fluid_rows: Vec<usize> = (0..mask.len()).filter(|&i| !mask[i]).collect();
                let walls: Vec<usize> = (0..mask.len()).filter(|&i| mask[i]).collect();
                (
                    Some(subset(set, &fluid_rows)),
                    Some(fluid_rows),
                    Some(mask),
                    Some(subset(set, &walls)),
                )
            }
        };
        // The input's walls first (rows, then arrays), then those of the files.
        let mut array_walls = Vec::with_capacity(self.wall_arrays.len());
        let options = ReadOptions {
            dim: self.input_dim,
            format: self.input_format.or_else(|| Format::from_path(input)),
        };
        for array in &self.wall_arrays {
            let walls = read_walls(input, Some(array), &options, &self.mode)?;
            if walls.dim() != set.dim() {
                return Err(CliError::WallFile {
                    path: input.to_path_buf(),
                    problem: format!(
                        "its particle array {array:?} holds {}D particles, the input {}D",
                        walls.dim(),
                        set.dim()
                    ),
                });
            }
            array_walls.push(walls);
        }
        let parts: Vec<&AnyParticleSet> = input_walls
            .iter()
            .chain(&array_walls)
            .chain(self.file_walls.iter().map(|(w, _)| w))
            .filter(|w| !w.is_empty())
            .collect();
        let walls = match parts[..] {
            [] => None,
            [one] => Some(one.clone()),
            _ => Some(join_any(&parts)?),
        };
        let count = walls.as_ref().map_or(0, AnyParticleSet::len);
        let mut domain = Domain::new();
        if let Some(w) = walls {
            domain = domain.with_walls(w);
        }
        for h in &self.solids {
            domain = domain.with_solid(*h);
        }
        for (mesh, _) in &self.meshes {
            domain = domain.with_solid_mesh(Arc::clone(mesh));
        }
        for p in &self.periodic {
            domain = domain.with_periodic(*p);
        }
        if let Some(name) = &self.phase_attribute {
            let phases = phases(frame, name, rows.as_deref())?;
            domain = domain.with_phases(phases);
        }
        Ok(FrameDomain {
            fluid,
            rows,
            wall_rows,
            domain,
            walls: count,
        })
    }
}

/// The phase numbers of the classified rows (`rows`, else every row) from the attribute
/// `name`; a value that is not an integer in `0..=u32::MAX` names its row and line.
fn phases(frame: &Frame, name: &str, rows: Option<&[usize]>) -> Result<Vec<u32>, CliError> {
    let attribute = point_attribute(frame, name, "--phase-attribute", "a phase number")?;
    let value = |i: usize| -> f64 {
        match &attribute.values {
            AttributeValues::Int(v) => v[i] as f64,
            AttributeValues::Float(v) => v[i],
        }
    };
    let phase = |i: usize| -> Result<u32, CliError> {
        let x = value(i);
        if x.is_finite() && x >= 0.0 && x <= f64::from(u32::MAX) && x.fract() == 0.0 {
            return Ok(x as u32);
        }
        Err(CliError::PhaseValue {
            path: frame.path.clone(),
            attribute: attribute.name.clone(),
            index: i,
            line: frame.line(i),
            value: x,
        })
    };
    match rows {
        Some(rows) => rows.iter().map(|&i| phase(i)).collect(),
        None => (0..frame.set.len()).map(phase).collect(),
    }
}

/// Reads one `--walls` file (or, with `array`, that particle array of a PySPH file) with
/// `options`, with its radii when `--radius-attribute` names an attribute it has. An empty
/// file is an error.
fn read_walls(
    path: &Path,
    array: Option<&str>,
    options: &ReadOptions,
    mode: &RadiusMode,
) -> Result<AnyParticleSet, CliError> {
    let what = match array {
        Some(array) => format!("its particle array {array:?} holds no particle"),
        None => "the file holds no particle".to_owned(),
    };
    // A PySPH file of several arrays (fluid and walls) as --walls would give its fluid.
    if array.is_none() && matches!(options.format, Some(Format::Hdf5 | Format::Npz)) {
        let arrays = boundary_io::particle_arrays(path, options)?;
        if arrays.len() > 1 {
            let names: Vec<String> = arrays
                .iter()
                .map(|(name, n)| format!("{name} ({n})"))
                .collect();
            return Err(CliError::WallFile {
                path: path.to_path_buf(),
                problem: format!(
                    "it holds several particle arrays ({}), so which are walls is unclear: \
                     name the wall array of the input's own file with --wall-array NAME",
                    names.join(", ")
                ),
            });
        }
    }
    // A file of no particle is named as the wall file it was meant to be.
    let no_particle = |error: boundary_io::IoError| match error {
        boundary_io::IoError::NoParticles { detail, .. } => CliError::WallFile {
            path: path.to_path_buf(),
            problem: format!("{what}: {detail}"),
        },
        other => other.into(),
    };
    let set = match mode {
        RadiusMode::PerParticle { attribute, scale } => {
            let frame = read_wall_frame(path, array, options, FrameParts::WithAttributes)
                .map_err(no_particle)?;
            if frame.attribute(attribute).is_some() {
                attach_radii(frame, attribute, *scale)?.0.set
            } else {
                frame.set
            }
        }
        RadiusMode::Uniform(_) => {
            read_wall_frame(path, array, options, FrameParts::Positions)
                .map_err(no_particle)?
                .set
        }
    };
    if set.is_empty() {
        return Err(CliError::WallFile {
            path: path.to_path_buf(),
            problem: what,
        });
    }
    Ok(set)
}

/// The particles `rows` of `set`, in that order, with their radii.
fn subset(set: &AnyParticleSet, rows: &[usize]) -> AnyParticleSet {
    match set {
        AnyParticleSet::D2(s) => s.subset(rows).into(),
        AnyParticleSet::D3(s) => s.subset(rows).into(),
    }
}

/// The particles of `parts` one after the other; radii where any part has them (factor 1
/// for the particles of a part without).
fn join<const D: usize>(parts: &[&ParticleSet<D>]) -> Result<ParticleSet<D>, CoreError>
where
    Dim<D>: SupportedDim,
{
    let positions: Vec<Point<D>> = parts
        .iter()
        .flat_map(|p| p.positions().iter().copied())
        .collect();
    let set = ParticleSet::new(positions)?;
    if parts.iter().all(|p| p.radii().is_none()) {
        return Ok(set);
    }
    let radii: Vec<f64> = parts
        .iter()
        .flat_map(|p| match p.radii() {
            Some(r) => r.to_vec(),
            None => vec![1.0; p.len()],
        })
        .collect();
    set.with_radii(radii)
}

/// [`join`] of sets of one dimension (checked by the callers).
fn join_any(parts: &[&AnyParticleSet]) -> Result<AnyParticleSet, CliError> {
    let d2: Option<Vec<&ParticleSet<2>>> = parts
        .iter()
        .map(|p| match p {
            AnyParticleSet::D2(s) => Some(s),
            AnyParticleSet::D3(_) => None,
        })
        .collect();
    if let Some(d2) = d2 {
        return Ok(join(&d2)?.into());
    }
    let d3: Option<Vec<&ParticleSet<3>>> = parts
        .iter()
        .map(|p| match p {
            AnyParticleSet::D3(s) => Some(s),
            AnyParticleSet::D2(_) => None,
        })
        .collect();
    match d3 {
        Some(d3) => Ok(join(&d3)?.into()),
        None => Err(CliError::Usage(
            "the wall particles mix 2D and 3D sets (--dim 2 reads a 3D file with one constant \
             axis as 2D)",
        )),
    }
}

/// The wall file at `path`, or the particle array `array` of it (a PySPH file), read once.
fn read_wall_frame(
    path: &Path,
    array: Option<&str>,
    options: &ReadOptions,
    parts: FrameParts,
) -> Result<Frame, boundary_io::IoError> {
    match array {
        Some(array) => boundary_io::read_array_frame(path, array, options, parts),
        None => read_frame(path, options, parts),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_attribute_lists_parse_or_say_what_is_wrong() {
        let s = parse_wall_attribute(" type = 0, 1.5 ").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            (s.name.as_str(), s.values.clone()),
            ("type", vec![0.0, 1.5])
        );
        assert_eq!(s.describe(), "type=0,1.5");
        for (bad, why) in [
            ("type", "expected NAME=V"),
            ("=1", "name is empty"),
            ("type=", "empty value"),
            ("type=1,,2", "empty value"),
            ("type=a", "'a' is not a finite number"),
            ("type=inf", "'inf' is not a finite number"),
        ] {
            let e = parse_wall_attribute(bad).unwrap_err();
            assert!(e.contains(why) && e.contains(bad), "{bad}: {e}");
        }
    }

    #[test]
    fn joined_walls_keep_radii_and_give_factor_one_to_the_others() {
        let a = ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap_or_else(|e| panic!("{e}"));
        let b = ParticleSet::<2>::from_rows(&[[1.0, 0.0], [2.0, 0.0]])
            .and_then(|s| s.with_radii(vec![0.5, 2.0]))
            .unwrap_or_else(|e| panic!("{e}"));
        let joined = join(&[&a, &b]).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(joined.len(), 3);
        assert_eq!(joined.radii(), Some(&[1.0, 0.5, 2.0][..]));
        let plain = join(&[&a, &a]).unwrap_or_else(|e| panic!("{e}"));
        assert!(plain.radii().is_none());
    }
}
