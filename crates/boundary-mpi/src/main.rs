//! `boundary-mpi`: boundary labels of a particle set split across MPI ranks.
//!
//! ```text
//! mpirun -np N boundary-mpi detect INPUT --radius R [--method NAME] [--set KEY=VALUE]...
//!        [--decomposition rcb|morton] [--output FILE] [--per-rank-output PATTERN]
//!        [--dim 2|3] [--format FMT] [--threads N] [--timings] [--json]
//! mpirun -np N boundary-mpi detect --per-rank-input 'part_{rank}.csv' --radius R ...
//! ```
//!
//! Phases (each ends in a collective, so its slowest rank is its wall time):
//! 1. **read**: a CSV INPUT is read by every rank, each the lines that start in its byte range
//!    (an exclusive prefix sum of the ranks' line and row counts numbers lines and particles);
//!    another format is read by rank 0; or every rank reads its own CSV file with an `index`
//!    column of global indices (`--per-rank-input`), which is then kept as the decomposition.
//! 2. **decompose** (not with per-rank input): every rank finds the owners of the particles it
//!    read by recursive coordinate bisection or Morton blocks, balanced by count, computed in
//!    parallel (boxes and counts by all-reduce, cuts by a distributed radix selection) and
//!    equal to `boundary::implement::decompose`'s owners of the whole set.
//! 3. **exchange**: every rank sends each particle to its owner (all-to-all).
//! 4. **halo**: ranks exchange boxes, send each other the strips within the halo width
//!    `detector.halo_width(r)` and keep the exact ghosts (see the library docs).
//! 5. **detect**: `detect_owned` on owned + ghosts.
//! 6. **gather**: labels and positions to rank 0, put in input order (with `--output`).
//! 7. **write**: rank 0 writes `--output` (the input with a `boundary` column, as
//!    `boundary detect` writes it), and/or every rank writes `--per-rank-output`.
//!
//! Errors that one rank meets are agreed on collectively (every rank stops at the same point);
//! the rank that met it prints it.

use boundary::{Dim, SupportedDim};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use boundary::{
    detector_with_params, parse_param, AnyParticleSet, BoundaryDetector, ParticleSet, Point, Radius,
};
use boundary_io::{
    read_csv_column, read_csv_header, read_particles, write_particles, Column, Format, IoError,
    ReadOptions,
};
use boundary_mpi::{
    bounding_box, global_indices, keep_ghosts, labels_in_input_order, parallel_morton_owners,
    parallel_rcb_owners, rank_path, strip_for, Reduce,
};
use clap::{Args, Parser, Subcommand, ValueEnum};
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;
use serde_json::json;

#[derive(Debug, Parser)]
#[command(
    name = "boundary-mpi",
    version,
    about = "Boundary particles of a particle set split across MPI ranks (run under mpirun)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Label every particle as boundary (1) or interior (0), split across the ranks.
    Detect(DetectArgs),
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Decomposition {
    /// Recursive coordinate bisection: boxes, cut across their longest side.
    Rcb,
    /// Blocks of consecutive particles in Morton (Z) order of cells of the halo width.
    Morton,
}

#[derive(Debug, Args)]
struct DetectArgs {
    /// Particle file: a CSV file is read in parallel (each rank a byte range), another format
    /// (.xyz/.txt, .ply, .vtk, .vtu, .vtp, .bgeo, .hdf5, .npz) by rank 0.
    #[arg(required_unless_present = "per_rank_input")]
    input: Option<PathBuf>,
    /// Every rank reads its own CSV file (`{rank}` is replaced by the rank) with columns
    /// x, y[, z] and `index` (the global index, 0..n over all files); its particles are the
    /// ones the rank owns (no rebalancing).
    #[arg(long, conflicts_with = "input", value_name = "PATTERN")]
    per_rank_input: Option<String>,
    /// Particle resolution r.
    #[arg(long, short, allow_negative_numbers = true)]
    radius: f64,
    /// Method name (see `boundary methods`).
    #[arg(long, short, default_value = "exact")]
    method: String,
    /// Method parameter, repeatable: `--set depth=4`.
    #[arg(long = "set", value_parser = parse_param, value_name = "KEY=VALUE")]
    params: Vec<(String, String)>,
    /// How the set is split across the ranks (ignored with --per-rank-input).
    #[arg(long, value_enum, default_value = "rcb")]
    decomposition: Decomposition,
    /// Rank 0 writes the particles in input order with a `boundary` column (0/1), format by
    /// extension, exactly as `boundary detect --output` does.
    #[arg(long, short)]
    output: Option<PathBuf>,
    /// Every rank writes its owned particles with columns `index` and `boundary` (`{rank}` is
    /// replaced by the rank; format by extension).
    #[arg(long, value_name = "PATTERN")]
    per_rank_output: Option<String>,
    /// Dimension of the scene; 2 on a file with x,y,z drops the constant axis.
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    dim: Option<u8>,
    /// Input format, when the extension does not say it.
    #[arg(long, value_parser = parse_format, value_name = "FMT")]
    format: Option<Format>,
    /// Worker threads per rank for the detection.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    threads: u16,
    /// Print the time of every phase (slowest and mean rank) and the halo sizes.
    #[arg(long)]
    timings: bool,
    /// Print one JSON object (counts, halo, phase times) on stdout.
    #[arg(long)]
    json: bool,
}

fn parse_format(text: &str) -> Result<Format, String> {
    text.parse()
}

/// An error after which every rank stops: `Here` on the rank that met it (which prints it),
/// `Elsewhere` on the others.
#[derive(Debug)]
enum Failure {
    Here(String),
    Elsewhere,
}

const PHASES: [&str; 7] = [
    "read",
    "decompose",
    "exchange",
    "halo",
    "detect",
    "gather",
    "write",
];

/// Per-rank measurements, gathered to rank 0 at the end.
#[derive(Debug, Default)]
struct Stats {
    seconds: [f64; 7],
    owned: u64,
    ghosts: u64,
    /// Strip particles this rank sent to others (before the receivers' exact filter).
    sent: u64,
    boundary: u64,
}

fn main() -> ExitCode {
    let Some((universe, _)) = mpi::initialize_with_threading(mpi::Threading::Funneled) else {
        eprintln!("boundary-mpi: error: MPI cannot be initialised");
        return ExitCode::FAILURE;
    };
    let world = universe.world();
    let rank = world.rank();
    let code = match Cli::try_parse() {
        Err(e) => {
            // Every rank parses the same arguments; one message is enough.
            if rank == 0 {
                let _ = e.print();
            }
            u8::from(e.use_stderr()) * 2
        }
        Ok(Cli {
            command: Command::Detect(args),
        }) => match detect(&world, &args) {
            Ok(()) => 0,
            Err(Failure::Here(message)) => {
                eprintln!("boundary-mpi: rank {rank}: error: {message}");
                1
            }
            Err(Failure::Elsewhere) => 1,
        },
    };
    drop(universe); // MPI_Finalize before the process exits
    ExitCode::from(code)
}

/// Makes a local result collective: if any rank failed, every rank returns an error.
fn agree<T>(world: &SimpleCommunicator, local: Result<T, String>) -> Result<T, Failure> {
    let mine = i32::from(local.is_err());
    let mut any = 0i32;
    world.all_reduce_into(&mine, &mut any, SystemOperation::max());
    match local {
        Err(message) => Err(Failure::Here(message)),
        Ok(_) if any != 0 => Err(Failure::Elsewhere),
        Ok(value) => Ok(value),
    }
}

/// A wall clock for phases.
struct Clock(f64);

impl Clock {
    fn start() -> Self {
        Clock(mpi::time())
    }
    /// Seconds since the start or the last lap.
    fn lap(&mut self) -> f64 {
        let now = mpi::time();
        let t = now - self.0;
        self.0 = now;
        t
    }
}

fn detect(world: &SimpleCommunicator, args: &DetectArgs) -> Result<(), Failure> {
    // Every rank sees the same arguments, so these fail on all ranks alike.
    let setup = detector_with_params(&args.method, &args.params)
        .map_err(|e| e.to_string())
        .and_then(|d| {
            Radius::new(args.radius)
                .map(|r| (d, r))
                .map_err(|e| e.to_string())
        })
        .and_then(|(d, r)| {
            if let Some(p) = &args.output {
                Format::from_path(p).ok_or_else(|| {
                    format!(
                        "{}: unknown output format (use .csv, .xyz, .ply or .vtk)",
                        p.display()
                    )
                })?;
            }
            if let Some(p) = &args.per_rank_output {
                rank_path(p, 0)?;
            }
            if let Some(p) = &args.per_rank_input {
                rank_path(p, 0)?;
            }
            Ok((d, r))
        });
    let (detector, r) = match setup {
        Ok(v) => v,
        Err(message) if world.rank() == 0 => return Err(Failure::Here(message)),
        Err(_) => return Err(Failure::Elsewhere),
    };
    let options = ReadOptions {
        dim: args.dim.map(usize::from),
        format: args.format,
    };
    let mut clock = Clock::start();
    let local = match (&args.input, &args.per_rank_input) {
        (Some(path), _) => {
            let format = args.format.or_else(|| Format::from_path(path));
            if format == Some(Format::Csv) {
                read_csv_parts(world, path, &options)?
            } else {
                read_on_rank_0(world, path, &options)?
            }
        }
        (None, Some(pattern)) => read_per_rank(world, pattern, &options)?,
        (None, None) => return Err(Failure::Here("no input".to_owned())),
    };
    let read_seconds = clock.lap();
    let run = Run {
        world,
        args,
        detector: detector.as_ref(),
        r,
        clock,
        read_seconds,
    };
    let Local {
        set,
        index,
        n,
        decompose,
    } = local;
    match set {
        AnyParticleSet::D2(set) => run.go::<2>(set, index, n, decompose),
        AnyParticleSet::D3(set) => run.go::<3>(set, index, n, decompose),
    }
}

/// This rank's particles after the read.
struct Local {
    /// Its particles (every rank's of one dimension).
    set: AnyParticleSet,
    /// Their global indices (particle numbers in the input).
    index: Vec<u64>,
    /// Particles over all ranks.
    n: u64,
    /// Whether the driver decomposes (the input's split is no decomposition) or keeps the
    /// split (per-rank input).
    decompose: bool,
}

/// Makes a local result collective, the way a read of the whole file reports it: if any rank
/// failed, the lowest rank that failed (the first part of the file with an error) prints its
/// error and every rank returns an error.
fn first_error<T>(world: &SimpleCommunicator, local: Result<T, String>) -> Result<T, Failure> {
    let size = world.size();
    let mine = if local.is_err() { world.rank() } else { size };
    let mut first = size;
    world.all_reduce_into(&mine, &mut first, SystemOperation::min());
    match local {
        Ok(value) if first == size => Ok(value),
        Err(message) if first == world.rank() => Err(Failure::Here(message)),
        _ => Err(Failure::Elsewhere),
    }
}

/// The parallel read of one CSV file: every rank reads the header, then the lines that start
/// in its byte range; an exclusive prefix sum of the ranks' newline and row counts gives each
/// rank its first line number (for messages) and its first global index.
fn read_csv_parts(
    world: &SimpleCommunicator,
    path: &Path,
    options: &ReadOptions,
) -> Result<Local, Failure> {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let text = |e: IoError| e.to_string();
    let header = first_error(world, read_csv_header(path, options).map_err(text))?;
    let chunk = first_error(
        world,
        header
            .read_chunk(path, header.part(rank, size))
            .map_err(text),
    )?;
    let counts = [chunk.newlines() as u64, chunk.rows() as u64];
    let mut before = [0u64; 2];
    world.exclusive_scan_into(&counts[..], &mut before[..], SystemOperation::sum());
    if rank == 0 {
        before = [0, 0]; // MPI_Exscan leaves rank 0's result undefined
    }
    let (line, first) = (
        header.first_data_line() + before[0] as usize,
        before[1] as usize,
    );
    let coords = first_error(world, chunk.parse(&header, line, first).map_err(text))?;
    drop(chunk);
    let mut n = 0u64;
    world.all_reduce_into(&counts[1], &mut n, SystemOperation::sum());
    // Which axes hold one value over the whole file (the dimension policy drops one of them).
    let stride = header.stride();
    let mut lo = vec![f64::INFINITY; stride];
    let mut hi = vec![f64::NEG_INFINITY; stride];
    for row in coords.chunks_exact(stride) {
        for k in 0..stride {
            lo[k] = lo[k].min(row[k]);
            hi[k] = hi[k].max(row[k]);
        }
    }
    let (mut all_lo, mut all_hi) = (lo.clone(), hi.clone());
    world.all_reduce_into(&lo[..], &mut all_lo[..], SystemOperation::min());
    world.all_reduce_into(&hi[..], &mut all_hi[..], SystemOperation::max());
    let constant: Vec<bool> = (0..stride)
        .map(|k| n == 0 || all_lo[k] == all_hi[k])
        .collect();
    let (set, _) = first_error(
        world,
        header.finish(&coords, n as usize, &constant).map_err(text),
    )?;
    let index = (before[1]..before[1] + counts[1]).collect();
    Ok(Local {
        set,
        index,
        n,
        decompose: true,
    })
}

/// Rank 0 reads the whole file (formats without a parallel read); the other ranks start
/// empty.
fn read_on_rank_0(
    world: &SimpleCommunicator,
    path: &Path,
    options: &ReadOptions,
) -> Result<Local, Failure> {
    let local = if world.rank() == 0 {
        read_particles(path, options)
            .map(Some)
            .map_err(|e| e.to_string())
    } else {
        Ok(None)
    };
    let set = agree(world, local)?;
    let mut header = set
        .as_ref()
        .map_or([0u64; 2], |s| [s.dim() as u64, s.len() as u64]);
    world.process_at_rank(0).broadcast_into(&mut header[..]);
    let [dim, n] = header;
    let set = match set {
        Some(set) => set,
        None => empty_set(dim).map_err(Failure::Here)?,
    };
    let index = (0..set.len() as u64).collect();
    Ok(Local {
        set,
        index,
        n,
        decompose: true,
    })
}

/// An empty set of `dim` dimensions.
fn empty_set(dim: u64) -> Result<AnyParticleSet, String> {
    match dim {
        2 => Ok(ParticleSet::<2>::new(Vec::new())
            .map_err(|e| e.to_string())?
            .to_any()),
        3 => Ok(ParticleSet::<3>::new(Vec::new())
            .map_err(|e| e.to_string())?
            .to_any()),
        d => Err(format!("unsupported dimension {d}")),
    }
}

/// Every rank reads its own file, with the global index of each particle; the split is kept.
fn read_per_rank(
    world: &SimpleCommunicator,
    pattern: &str,
    options: &ReadOptions,
) -> Result<Local, Failure> {
    let local = rank_path(pattern, world.rank()).and_then(|path| {
        let set = match read_particles(Path::new(&path), options) {
            Ok(set) => set,
            // A rank may own no particle at a step: its file is a header without rows, an
            // empty set of the dimension the header names.
            Err(IoError::NoParticles { dim: Some(d), .. }) => empty_set(d as u64)?,
            Err(e) => return Err(e.to_string()),
        };
        let column = read_csv_column(Path::new(&path), "index")
            .map_err(|e| format!("{e} (per-rank input needs a CSV file with an `index` column)"))?;
        let index = global_indices(&column, &path)?;
        Ok((set, index))
    });
    let (set, index) = agree(world, local)?;
    // The files must agree on the dimension.
    let mine = set.dim() as u64;
    let (mut lo, mut hi) = (0u64, 0u64);
    world.all_reduce_into(&mine, &mut lo, SystemOperation::min());
    world.all_reduce_into(&mine, &mut hi, SystemOperation::max());
    if lo != hi {
        return Err(if mine == lo {
            Failure::Here(format!("the per-rank files mix {lo}D and {hi}D sets"))
        } else {
            Failure::Elsewhere
        });
    }
    let local_n = index.len() as u64;
    let mut n = 0u64;
    world.all_reduce_into(&local_n, &mut n, SystemOperation::sum());
    Ok(Local {
        set,
        index,
        n,
        decompose: false,
    })
}

/// The all-reduces of the parallel decomposition.
struct MpiReduce<'a>(&'a SimpleCommunicator);

impl MpiReduce<'_> {
    fn all<T: Copy + mpi::datatype::Equivalence>(&self, values: &mut [T], op: SystemOperation) {
        // Every rank reduces slices of the same length; none for an empty one.
        if !values.is_empty() {
            let mine = values.to_vec();
            self.0.all_reduce_into(&mine[..], values, op);
        }
    }
}

impl Reduce for MpiReduce<'_> {
    fn sum(&self, values: &mut [u64]) {
        self.all(values, SystemOperation::sum());
    }
    fn max_u64(&self, values: &mut [u64]) {
        self.all(values, SystemOperation::max());
    }
    fn min(&self, values: &mut [f64]) {
        self.all(values, SystemOperation::min());
    }
}

/// Counts and displacements (in elements of `per` values each) of a variable-count
/// collective; an error when they exceed MPI's `int` counts.
fn layout(counts: &[usize], per: usize) -> Result<(Vec<Count>, Vec<Count>), String> {
    let mut c = Vec::with_capacity(counts.len());
    let mut d = Vec::with_capacity(counts.len());
    let mut offset = 0usize;
    for &k in counts {
        let too_many = || {
            format!(
                "a message of more than {} values (MPI counts are 32-bit); use more ranks or \
                 --per-rank-input",
                Count::MAX
            )
        };
        let values = k.checked_mul(per).ok_or_else(too_many)?;
        c.push(Count::try_from(values).map_err(|_| too_many())?);
        d.push(Count::try_from(offset).map_err(|_| too_many())?);
        offset += values;
    }
    Ok((c, d))
}

fn flatten<const D: usize>(points: &[Point<D>]) -> Vec<f64> {
    points.iter().flat_map(|p| p.iter().copied()).collect()
}

fn unflatten<const D: usize>(coords: &[f64]) -> Vec<Point<D>> {
    coords
        .chunks_exact(D)
        .map(|c| Point::<D>::from_fn(|k, _| c[k]))
        .collect()
}

struct Run<'a> {
    world: &'a SimpleCommunicator,
    args: &'a DetectArgs,
    detector: &'a dyn BoundaryDetector,
    r: Radius,
    clock: Clock,
    read_seconds: f64,
}

impl Run<'_> {
    /// The pipeline in `D` dimensions from this rank's particles `set` with their global
    /// indices `index` (`n` over all ranks): decomposed and moved to their owners
    /// (`decompose`), or owned where they are.
    fn go<const D: usize>(
        mut self,
        set: ParticleSet<D>,
        index: Vec<u64>,
        n: u64,
        decompose: bool,
    ) -> Result<(), Failure>
    where
        AnyParticleSet: From<ParticleSet<D>>,
        Dim<D>: SupportedDim,
    {
        let world = self.world;
        let size = world.size() as usize;
        let w = self.detector.halo_width(self.r);
        let mut stats = Stats::default();
        stats.seconds[0] = self.read_seconds;
        let n = n as usize;
        let points = set.positions();

        // Owned particles (ascending global index) of this rank.
        let mut pairs: Vec<(u64, Point<D>)> = if decompose && size > 1 {
            let reduce = MpiReduce(world);
            let owner = match self.args.decomposition {
                Decomposition::Rcb => parallel_rcb_owners(&reduce, points, &index, size),
                Decomposition::Morton => parallel_morton_owners(&reduce, points, &index, size, w),
            };
            stats.seconds[1] = self.clock.lap();
            self.exchange(points, &index, &owner)?
        } else {
            index.into_iter().zip(points.iter().copied()).collect()
        };
        drop(set);
        pairs.sort_unstable_by_key(|&(i, _)| i);
        let (owned_index, owned): (Vec<u64>, Vec<Point<D>>) = pairs.into_iter().unzip();
        // The exchange phase ends with the owned particles in global-index order.
        stats.seconds[2] = self.clock.lap();
        stats.owned = owned.len() as u64;

        // Halo exchange.
        let (ghosts, ghost_index) = self.exchange_halo(&owned, &owned_index, w, &mut stats)?;
        stats.ghosts = ghosts.len() as u64;
        stats.seconds[3] = self.clock.lap();

        // Detection on owned + ghosts.
        let labels = {
            let n_owned = owned.len();
            let mut local = owned.clone();
            local.extend_from_slice(&ghosts);
            drop(ghosts);
            drop(ghost_index);
            let result = ParticleSet::new(local)
                .map_err(|e| e.to_string())
                .and_then(|set| {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(usize::from(self.args.threads))
                        .build()
                        .map_err(|e| format!("cannot start worker threads: {e}"))?;
                    pool.install(|| {
                        self.detector
                            .detect_owned(&AnyParticleSet::from(set), n_owned, self.r)
                            .map_err(|e| e.to_string())
                    })
                })
                .map(|d| {
                    d.labels
                        .as_slice()
                        .iter()
                        .map(|&b| u8::from(b))
                        .collect::<Vec<u8>>()
                });
            agree(world, result)?
        };
        stats.boundary = labels.iter().map(|&l| u64::from(l)).sum();
        stats.seconds[4] = self.clock.lap();

        // Gather to rank 0 (only what an --output needs).
        let gathered = if self.args.output.is_some() {
            let gathered = self.gather(&owned, &owned_index, &labels, n)?;
            stats.seconds[5] = self.clock.lap();
            gathered
        } else {
            None
        };

        // Write.
        let mut written = Ok(());
        if let (Some(path), Some((full_labels, set))) = (&self.args.output, gathered) {
            // Rank 0 gathered the set with the labels.
            let flags: Vec<i64> = full_labels.iter().map(|&l| i64::from(l)).collect();
            written = write_particles(
                path,
                None,
                &AnyParticleSet::from(set),
                &[("boundary", Column::Int(&flags))],
            )
            .map_err(|e| e.to_string());
        }
        if written.is_ok() {
            if let Some(pattern) = &self.args.per_rank_output {
                written = rank_path(pattern, world.rank()).and_then(|path| {
                    let set = ParticleSet::new(owned.clone()).map_err(|e| e.to_string())?;
                    let idx: Vec<i64> = owned_index.iter().map(|&i| i as i64).collect();
                    let flags: Vec<i64> = labels.iter().map(|&l| i64::from(l)).collect();
                    write_particles(
                        Path::new(&path),
                        None,
                        &AnyParticleSet::from(set),
                        &[
                            ("index", Column::Int(&idx)),
                            ("boundary", Column::Int(&flags)),
                        ],
                    )
                    .map_err(|e| e.to_string())
                });
            }
        }
        agree(world, written)?;
        stats.seconds[6] = self.clock.lap();
        self.report(&stats, n, D);
        Ok(())
    }

    /// Sends every other rank the owned particles within `w` of its box; returns the ghosts
    /// (within `w` of an owned particle), ascending by global index.
    fn exchange_halo<const D: usize>(
        &self,
        owned: &[Point<D>],
        owned_index: &[u64],
        w: f64,
        stats: &mut Stats,
    ) -> Result<(Vec<Point<D>>, Vec<u64>), Failure>
    where
        Dim<D>: SupportedDim,
    {
        let world = self.world;
        let size = world.size() as usize;
        let me = world.rank() as usize;
        // Boxes: lo then hi; an empty rank publishes an empty box (lo > hi).
        let my_box: Vec<f64> = match bounding_box(owned) {
            Some((lo, hi)) => lo.iter().chain(hi.iter()).copied().collect(),
            None => [f64::INFINITY; D]
                .into_iter()
                .chain([f64::NEG_INFINITY; D])
                .collect(),
        };
        let mut boxes = vec![0.0f64; 2 * D * size];
        world.all_gather_into(&my_box[..], &mut boxes[..]);
        let mut send: Vec<Vec<usize>> = vec![Vec::new(); size];
        for (q, b) in boxes.chunks_exact(2 * D).enumerate() {
            let (lo, hi) = (
                Point::<D>::from_fn(|k, _| b[k]),
                Point::<D>::from_fn(|k, _| b[D + k]),
            );
            if q != me && (0..D).all(|k| lo[k] <= hi[k]) {
                send[q] = strip_for(owned, &(lo, hi), w);
            }
        }
        let send_counts: Vec<usize> = send.iter().map(Vec::len).collect();
        stats.sent = send_counts.iter().sum::<usize>() as u64;
        let send_coords: Vec<f64> = send
            .iter()
            .flatten()
            .flat_map(|&i| owned[i].iter().copied())
            .collect();
        let send_index: Vec<u64> = send.iter().flatten().map(|&i| owned_index[i]).collect();
        let (recv_coords, recv_index) =
            self.send_by_rank(&send_counts, &send_coords, &send_index, D)?;
        let candidates = unflatten::<D>(&recv_coords);
        let kept = agree(
            world,
            keep_ghosts(owned, &candidates, w).map_err(|e| e.to_string()),
        )?;
        let mut ghosts: Vec<(u64, Point<D>)> = kept
            .into_iter()
            .map(|j| (recv_index[j], candidates[j]))
            .collect();
        ghosts.sort_by_key(|&(i, _)| i);
        Ok(ghosts.into_iter().map(|(i, p)| (p, i)).unzip())
    }

    /// One all-to-all of particles: `send_counts[q]` particles go to rank `q`, their `per`
    /// coordinates each in `send_coords` and their global indices in `send_index`, both in
    /// rank order. Returns the coordinates and indices received, in rank order.
    fn send_by_rank(
        &self,
        send_counts: &[usize],
        send_coords: &[f64],
        send_index: &[u64],
        per: usize,
    ) -> Result<(Vec<f64>, Vec<u64>), Failure> {
        let world = self.world;
        let send_counts64: Vec<u64> = send_counts.iter().map(|&c| c as u64).collect();
        let mut recv_counts64 = vec![0u64; send_counts.len()];
        world.all_to_all_into(&send_counts64[..], &mut recv_counts64[..]);
        let recv_counts: Vec<usize> = recv_counts64.iter().map(|&c| c as usize).collect();
        let layouts = layout(send_counts, per).and_then(|sc| {
            Ok((
                sc,
                layout(send_counts, 1)?,
                layout(&recv_counts, per)?,
                layout(&recv_counts, 1)?,
            ))
        });
        let ((scc, scd), (sic, sid), (rcc, rcd), (ric, rid)) = agree(world, layouts)?;
        let total: usize = recv_counts.iter().sum();
        let mut recv_coords = vec![0.0f64; total * per];
        let mut recv_index = vec![0u64; total];
        let sp = Partition::new(send_coords, &scc[..], &scd[..]);
        let mut rp = PartitionMut::new(&mut recv_coords[..], &rcc[..], &rcd[..]);
        world.all_to_all_varcount_into(&sp, &mut rp);
        let sp = Partition::new(send_index, &sic[..], &sid[..]);
        let mut rp = PartitionMut::new(&mut recv_index[..], &ric[..], &rid[..]);
        world.all_to_all_varcount_into(&sp, &mut rp);
        Ok((recv_coords, recv_index))
    }

    /// Sends every local particle to its owner (`owner[k]` for particle `k`); returns the
    /// particles this rank owns with their global indices, in no order.
    fn exchange<const D: usize>(
        &self,
        points: &[Point<D>],
        index: &[u64],
        owner: &[usize],
    ) -> Result<Vec<(u64, Point<D>)>, Failure> {
        let world = self.world;
        let size = world.size() as usize;
        let mut send_counts = vec![0usize; size];
        for &o in owner {
            send_counts[o] += 1;
        }
        // The send buffers in owner order (a counting sort, stable in the local order).
        let mut next: Vec<usize> = send_counts
            .iter()
            .scan(0, |start, &c| {
                let at = *start;
                *start += c;
                Some(at)
            })
            .collect();
        let mut send_coords = vec![0.0f64; points.len() * D];
        let mut send_index = vec![0u64; points.len()];
        for ((p, &i), &o) in points.iter().zip(index).zip(owner) {
            let at = next[o];
            next[o] += 1;
            send_index[at] = i;
            for k in 0..D {
                send_coords[at * D + k] = p[k];
            }
        }
        let (recv_coords, recv_index) =
            self.send_by_rank(&send_counts, &send_coords, &send_index, D)?;
        Ok(recv_index
            .into_iter()
            .zip(unflatten::<D>(&recv_coords))
            .collect())
    }

    /// Gathers labels and positions to rank 0 and puts them in input order; `Some((labels,
    /// set))` on rank 0, `None` elsewhere.
    fn gather<const D: usize>(
        &self,
        owned: &[Point<D>],
        owned_index: &[u64],
        labels: &[u8],
        n: usize,
    ) -> Result<Option<(Vec<u8>, ParticleSet<D>)>, Failure>
    where
        Dim<D>: SupportedDim,
    {
        let world = self.world;
        let size = world.size() as usize;
        if size == 1 {
            // The owned particles are the set in input order.
            let result = labels_in_input_order(n, owned_index, labels).and_then(|ordered| {
                let set = ParticleSet::new(owned.to_vec()).map_err(|e| e.to_string())?;
                Ok((ordered, set))
            });
            return agree(world, result).map(Some);
        }
        let root = world.process_at_rank(0);
        let count = owned.len() as u64;
        let coords = flatten(owned);
        // Open MPI's MPI_IN_PLACE is the address 1, which is also where Rust puts an empty
        // slice of bytes; an allocated buffer keeps an empty rank's labels from reading as
        // "in place" (MPI_ERR_ARG in MPI_Gatherv).
        let mut label_buf: Vec<u8> = Vec::with_capacity(labels.len().max(1));
        label_buf.extend_from_slice(labels);
        let labels = &label_buf[..];
        if world.rank() != 0 {
            root.gather_into(&count);
            agree(world, Ok(()))?;
            root.gather_varcount_into(owned_index);
            root.gather_varcount_into(labels);
            root.gather_varcount_into(&coords[..]);
            agree(world, Ok(()))?;
            return Ok(None);
        }
        let mut counts64 = vec![0u64; size];
        root.gather_into_root(&count, &mut counts64[..]);
        let counts: Vec<usize> = counts64.iter().map(|&c| c as usize).collect();
        let total: usize = counts.iter().sum();
        let ((ic, id), (cc, cd)) = agree(
            world,
            layout(&counts, 1).and_then(|i| Ok((i, layout(&counts, D)?))),
        )?;
        let mut index = vec![0u64; total];
        let mut all_labels = vec![0u8; total];
        {
            let mut part = PartitionMut::new(&mut index[..], &ic[..], &id[..]);
            root.gather_varcount_into_root(owned_index, &mut part);
            let mut part = PartitionMut::new(&mut all_labels[..], &ic[..], &id[..]);
            root.gather_varcount_into_root(labels, &mut part);
        }
        let mut all = vec![0.0f64; total * D];
        {
            let mut part = PartitionMut::new(&mut all[..], &cc[..], &cd[..]);
            root.gather_varcount_into_root(&coords[..], &mut part);
        }
        let result = labels_in_input_order(n, &index, &all_labels).and_then(|ordered| {
            // Every index is in range and given once (checked above).
            let mut points = vec![Point::<D>::zeros(); n];
            for (k, p) in unflatten::<D>(&all).into_iter().enumerate() {
                points[index[k] as usize] = p;
            }
            Ok((
                ordered,
                ParticleSet::new(points).map_err(|e| e.to_string())?,
            ))
        });
        agree(world, result).map(Some)
    }

    /// Gathers the statistics to rank 0 and prints them.
    fn report(&self, stats: &Stats, n: usize, dim: usize) {
        let world = self.world;
        let size = world.size() as usize;
        let root = world.process_at_rank(0);
        let mut mine = stats.seconds.to_vec();
        mine.extend([
            stats.owned as f64,
            stats.ghosts as f64,
            stats.sent as f64,
            stats.boundary as f64,
        ]);
        let width = mine.len();
        if world.rank() != 0 {
            root.gather_into(&mine[..]);
            return;
        }
        let mut all = vec![0.0f64; width * size];
        root.gather_into_root(&mine[..], &mut all[..]);
        let rows: Vec<&[f64]> = all.chunks_exact(width).collect();
        let col = |k: usize| rows.iter().map(move |r| r[k]);
        let max = |k: usize| col(k).fold(0.0f64, f64::max);
        let sum = |k: usize| col(k).sum::<f64>();
        let owned = sum(7);
        let ghosts = sum(8);
        let sent = sum(9);
        let boundary = sum(10) as u64;
        let halo_fraction = if owned > 0.0 { ghosts / owned } else { 0.0 };
        let owned_min = col(7).fold(f64::INFINITY, f64::min);
        let owned_max = max(7);
        let total: f64 = (0..PHASES.len()).map(max).sum();
        let args = self.args;
        if args.json {
            let phases: serde_json::Map<String, serde_json::Value> = PHASES
                .iter()
                .enumerate()
                .map(|(k, name)| ((*name).to_owned(), json!(max(k))))
                .collect();
            let object = json!({
                "method": self.detector.name(),
                "params": self.detector.describe().to_string(),
                "n": n,
                "dim": dim,
                "radius": self.r.get(),
                "ranks": size,
                "threads_per_rank": args.threads,
                "decomposition": if args.per_rank_input.is_some() { "per-rank input" } else {
                    match args.decomposition { Decomposition::Rcb => "rcb", Decomposition::Morton => "morton" }
                },
                "halo_width": self.detector.halo_width(self.r),
                "boundary": boundary,
                "owned_min": owned_min,
                "owned_max": owned_max,
                "ghosts": ghosts,
                "halo_fraction": halo_fraction,
                "strip_sent": sent,
                "seconds_max": phases,
                "seconds_total": total,
            });
            println!("{object}");
        } else {
            eprintln!(
                "{}: {boundary} of {n} particles boundary, {dim}D, r = {}, {} on {size} rank{} \
                 ({} thread{} each) in {total:.3} s",
                args.input.as_ref().map_or_else(
                    || args.per_rank_input.clone().unwrap_or_default(),
                    |p| p.display().to_string()
                ),
                self.r.get(),
                self.detector.name(),
                if size == 1 { "" } else { "s" },
                args.threads,
                if args.threads == 1 { "" } else { "s" },
            );
        }
        if args.timings {
            eprintln!("phase        slowest rank   mean rank");
            for (k, name) in PHASES.iter().enumerate() {
                eprintln!(
                    "{name:<10} {:>12.4} s {:>10.4} s",
                    max(k),
                    sum(k) / size as f64
                );
            }
            eprintln!(
                "owned per rank {owned_min}..{owned_max}; ghosts {ghosts} (halo fraction \
                 {halo_fraction:.4} of owned; width {}); strip particles sent {sent}",
                self.detector.halo_width(self.r)
            );
        }
    }
}
