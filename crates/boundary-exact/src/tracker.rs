//! Incremental `exact` labels over time steps: [`Tracker`].
//!
//! A solver calls detection every time step, while each particle moves a small fraction of the
//! spacing. [`Tracker::update`] returns, at every step, the labels of a full `exact` detection
//! of that step, bit for bit, and recomputes only the particles whose label may have changed.
//!
//! # The certificate: a coverage depth that is Lipschitz in the positions
//! Uniform radius `r`, particle `i`, the other particles `p_j` (walls included). Let
//! `d(x) = min_{j≠i} |x − p_j|` and `G_i = max_{x ∈ S_i} d(x)`. When no particle coincides
//! with `p_i`, a point `x` of `S_i` is uncovered iff `d(x) > r`, so `i` is **boundary iff
//! `G_i > r`** (coincident particles are excluded by the definition; see below).
//!
//! *Lipschitz.* Each `|p_i + r·u − p_j|` (`u` a unit vector) moves by at most
//! `|Δp_i| + |Δp_j|` when the particles move by `Δ`; a minimum over `j` and a maximum over `u`
//! keep that bound, so `|ΔG_i| <= |Δp_i| + sup_j |Δp_j|`, between any two configurations,
//! whatever happened in between and whichever particles entered or left the neighbourhood
//! (the index set is all particles, fixed). So if at the last evaluation `|G_i − r| >= b_i`
//! (the **budget**) and since then `|Δp_i| + sup_j |Δp_j| < b_i`, the sign of `G_i − r`, hence
//! the label, has not changed, provided no particle coincides with `p_i` at either time.
//!
//! *Coincidence.* At the evaluation, a particle with an exact duplicate gets budget 0 (it is
//! recomputed at every step). Otherwise its nearest neighbour lies at `m_i > 0` (or beyond
//! `2r`), and no particle can coincide with it while the movement stays below `m_i`: the
//! interior budget is capped at `min(m_i, 2r)`. The boundary budget needs no cap: a particle
//! that comes to coincide with `p_i` leaves the cover, which only widens the gap it bounds.
//!
//! *Interior budget* (the float cell proves `G_i <= r`). Let `g(x) = min_j (|x − p_j|² −
//! |x − p_i|²)` over the neighbours within `2r` (a subset of all particles, so on `S_i`
//! `d(x)² − r² <= g(x)`). `g` is concave (a minimum of affine functions), `g(p_i) = m_i²`, and
//! `{g >= 0}` is the Voronoi cell `V` of `p_i` among its neighbours. Let `ρ < r` bound the reach
//! of `V` within the box `[p_i − r, p_i + r]^D` (which holds `S_i`). Along the segment from
//! `p_i` to `x ∈ S_i` (inside the box), `g` falls from `m_i²` to `0` at some `s <= ρ`; by
//! concavity beyond `s` it stays below the chord's extension: `g(x) <= −m_i²(r − s)/s <=
//! −m_i²(r − ρ)/ρ =: −κ`. So `G_i² <= r² − κ` and `r − G_i >= r − √(r² − κ) >= κ/(2r)`:
//! **`b_i = m_i²(r − ρ)/(2rρ)`**. `ρ` is the float cell's reach plus its proven error bound `τ`
//! (crate docs, "Exactness": the exact reach lies within `τ` of the float reach), with the
//! cell clipped to the end (not stopped at `1 − 1e-6`, as a single detection does).
//!
//! *Boundary budget* (the float cell proves `G_i > r`): a witness. `x` is the point of `S_i`
//! in the direction of the float cell's farthest vertex, and `G_i >= d(x)` (with the
//! particles that coincide with `p_i` left out of `d`, as the definition has it, `d` is only
//! larger). Split the others at the evaluation into `W`, those within `1.5r` of `x`, and the
//! rest, farther than `1.5r`. The witness moves with `i` (`x − p_i` fixed), so each distance
//! `|x − p_j| = |(x − p_i) − q_j|` moves by at most `|Δq_j|`, the movement of `j` relative to
//! `i`. The label stays boundary while every particle stays farther than `r` from the witness,
//! which two budgets guarantee: the **near budget `b_i = d_W(x) − r`** (`d_W` the distance to
//! the nearest member of `W`; `1.5r` if none) against the movement of the members of `W`
//! relative to `i`, and the **far budget `0.5r`** against `|Δp_i| + sup_j |Δp_j|`, which bounds
//! every other `|Δq_j|`. `b_i` is positive when `x` is uncovered (it usually is, being near
//! the cell's farthest point; otherwise `b_i = 0`). No cell topology is trusted here: only
//! the distances from one point.
//!
//! *Interior: only the cell's neighbours, relative to `i`.* The bound above holds with `g`
//! over any subset `J` of the particles whose cell (with the box) reaches within `ρ`: the
//! float cell uses exactly such a `J`, its first neighbours nearest first (those it took
//! before no bisector could reach it). With `G_J` the same maximum over `J` only, `G_i <= G_J`
//! (fewer balls cover less; a particle that comes to coincide with `p_i` leaves the cover,
//! which `G_J` never counted), and `G_J` depends only on the offsets `q_j = p_j − p_i`, each
//! term moving by at most `|Δq_j|`: `G_J` moves by at most `max_{j ∈ J} |Δq_j|`, the largest
//! movement of a cell neighbour *relative to `i`*, and no other particle matters. In a smooth
//! flow that is the velocity gradient times the distance, far below the displacement itself.
//! (The cap `m_i` keeps the members of `J` off `p_i`.)
//!
//! *Bookkeeping.* Per particle, the offsets `q_j` of the neighbours it watches (`J`, or `W`)
//! at its evaluation, and a bound on `max_j |Δq_j|` since then, against its budget; per
//! boundary particle also its own displacement since the evaluation plus the running sum of
//! each step's largest displacement (fluid and walls), which bounds `sup_j |Δp_j|`, against
//! the far budget. A particle is recomputed when either reaches its budget. The neighbours are
//! read only when the bound might have reached the budget: in one step every `|Δq_j|` grows
//! by at most twice that step's largest displacement, so the bound proven at the last check
//! plus twice the running sum's growth since bounds it now; while that stays below the
//! budget nothing is read, otherwise `max_j |q_j(now) − q_j(eval)|` is measured (a new bound,
//! from the current positions).
//!
//! *Rounding.* Every quantity compared above carries a relative rounding error of a few `u`
//! (`u = 2^-53`): distances, the running sum (rounded up at each step), the budgets' formula.
//! A measured `|q_j(now) − q_j(eval)|` also gains `64u·(r + |Δq_j|)` for the rounding of the
//! offsets (each within `2.5r` of the particle at its evaluation), and `3e-7·r` for their
//! storage in units of `r` in single precision (each coordinate rounded to 24 bits: at most
//! `√3·2.5r·2^-24` and a few `u`, below `2.6e-7·r`).
//! Budgets are shrunk by the factor `1 − 1e-9` and movements grown by `1 + 1e-9`, and the
//! witness loses `1e-12·r + 1e-14·|p_i|_∞` for the rounding of `x` itself (its distance from
//! `S_i` is below `4u·(r + √D·|p_i|_∞)`). Particles whose float cell does not decide within
//! its bound (near-ties, near-degenerate clips, perfect lattices) get the label of the full
//! decision (certificates, exact predicate) and budget 0: they are recomputed at every step.
//! So every label is the exact label of the step, as a full detection gives it.
//!
//! # Inflow and outflow
//! With stable ids ([`Tracker::update_with_ids`]) particles may come and go between two
//! updates. Each case reduces to the argument above by a *fictitious history* over a fixed
//! index set, which agrees with the real configuration at every update from now on:
//!
//! - *A particle `j` leaves:* in the fictitious history `j` stays, frozen where it was last
//!   seen. Its movement is 0, so every recorded movement still bounds the fictitious one. An
//!   interior certificate over `J` holds as long as every member of `J` is a real particle:
//!   the interior particles with `j ∈ J` are evaluated again, the others keep their budget
//!   (`G_i <= G_J` needs `J`, not the rest). A boundary particle keeps its budgets, `j` leaving
//!   its list `W`: the real configuration has fewer balls than the fictitious one, so every
//!   distance from the witness is at least the fictitious one.
//! - *A particle `k` arrives at `a_k`:* in the fictitious history `k` was at `a_k` all along,
//!   frozen until now. Interior certificates are unaffected (`k ∉ J`). For a boundary particle
//!   evaluated at `e_i`, the witness lay within `r` (plus its rounding) of `e_i`; if
//!   `|e_i − a_k| > 2.5r`, then `k` was farther than `1.5r` from the witness, one of the far
//!   particles, whose movement since (none until now, then counted in each step's largest)
//!   the far budget already bounds. Boundary particles with a new particle within `2.5r` of
//!   `e_i` (grown by `1e-9` relative and the witness's rounding) are evaluated again, as are
//!   the new particles.
//!
//! Walls have no ids: they are matched by place, as in [`Tracker::move_walls`].
//!
//! # Reuse
//! The tracker holds the particles in an order of its own, spatial (the grid's cell order)
//! from the first update on; the caller may list them in any order from step to step when it
//! passes ids (a solver that sorts its particles into cells every step loses nothing but a
//! gather of the positions and a scatter of the labels). Besides the budgets, labels and each
//! interior particle's certificate neighbours, an update keeps the neighbour grid of the last
//! evaluation as it was sorted, untouched while no particle may have drifted more than `0.5r`
//! from there (the Verlet-list rule with a skin of `r`). The drift is bounded by the growth of
//! the running sum of the steps' largest displacements since the grid was sorted, so nothing
//! is computed per particle to keep it: a query of an evaluated particle scans `drift` farther
//! and tests the particles it finds at their current positions, so it finds the same particles
//! at the same distances as a new grid would. The labels and the proofs of the budgets do not
//! depend on the reuse.
//!
//! # Threads
//! An update runs on the thread that calls it. A solver's step leaves the tracker's workers
//! asleep for milliseconds, and handing them work costs some tens of microseconds twice
//! (waking them, being woken when they are done): about as much as the whole update of a
//! set of ten thousand particles. So only the large parts go to the workers (the tracker's
//! pool, or the rayon pool the update is called on): the passes over every particle from
//! 16,384 particles on (in pieces of 8,192), the evaluations from 128 in one step, a new
//! neighbour grid from 32,768 particles, a full detection. Smaller parts run on the calling
//! thread, and an update that has only those never touches the pool.
//!
//! # Fallbacks and scope
//! - The first update, a change of the dimension or of the number of walls start over
//!   (every particle evaluated); so does a change of the particle count without ids, and the
//!   first update with ids after one without.
//! - A large step: when more than 60 % of the particles would be recomputed, the step runs a
//!   full detection instead. The budgets are then spent: the next 1, 2, 4, … 32 steps (doubling
//!   at each fallback in a row) run full detections, then every particle is evaluated again.
//!   An evaluation costs about 1.5 times a particle of a full detection, so a sequence of
//!   large steps costs a few percent more than full detections (the sweep's sequence tier
//!   measures it at 0.5 spacing per step).
//! - Walls ([`Domain::with_walls`]) cover like particles: they may move
//!   ([`Tracker::move_walls`]), and their movement counts in the step's largest displacement.
//!   Walls that were not moved since the last update (never moved, or given again bit for bit)
//!   cost nothing per step: their movement is known to be zero and is not computed.
//! - Solids, periodic axes, phases, solid meshes and per-particle radii are honoured by a full
//!   detection in the domain at every step ([`Tracker::recomputed`] then reports every
//!   particle): labels as a single detection, without the saving; with phases, the interface
//!   labels too ([`Tracker::set_phases`], [`Tracker::interface`]).

use crate::cell::{Clipper, ConvexCell, Polygon, Polyhedron};
use crate::{cell_margin, classify, detect_with, Near, Neighbours, Scratch, NEAR_SLACK, U};

/// The neighbours within `FIRST_REACH·r` are gathered first (units of `r`): an interior cell
/// clipped to the end reaches about `0.6r` on a jittered lattice at `r = 1.5` spacings, within
/// half of it, so it needs no other neighbour.
const FIRST_REACH: f64 = 1.6;
use boundary_core::{
    AnyParticleSet, CoreError, DetectError, Domain, Labels, NeighbourGrid, ParticleSet, Point,
    Radius,
};
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::sync::Arc;

/// Budgets shrink and movements grow by this relative amount: far above the few `u` of
/// relative rounding in the distances, sums and formulas compared (module docs).
const ROUNDING: f64 = 1e-9;

/// The witness looks for particles within `WITNESS_REACH·r` of its point: the boundary budget
/// is at most `(WITNESS_REACH − 1)·r`.
const WITNESS_REACH: f64 = 1.5;

/// The neighbour grid is reused, as it was sorted, while no particle (fluid or wall) may have
/// drifted more than `SKIN·r` from where it sorted them: queries then scan up to `SKIN·r`
/// farther (module docs, "Reuse").
const SKIN: f64 = 0.5;

/// More than this fraction of particles to recompute: a full detection is cheaper (an
/// evaluation costs about 1.5 times a particle of a full detection: the cell is clipped to
/// the end, and the witness needs one more query).
const FULL_FRACTION: f64 = 0.6;

/// At most this many full detections in a row before the tracker evaluates every particle
/// again (the amortised cost of a retry: `0.5/MAX_BACKOFF` of a detection per step).
const MAX_BACKOFF: u32 = 32;

/// The per-step passes over every particle (movements, budgets) run in pieces of at least
/// this many particles: below twice as many, on the calling thread alone. A piece costs
/// about 0.1 ms, well above what waking another worker costs.
const PASS_PIECE: usize = 8192;

/// Evaluations run in pieces of at least this many particles (one evaluation costs a few
/// microseconds).
const EVALUATION_PIECE: usize = 16;

/// Fewer evaluations than this in a step run on the calling thread: they cost a few tenths
/// of a millisecond, and handing work to workers that slept through the solver's step costs
/// some tens of microseconds, twice (waking them, being woken when they are done).
const EVALUATION_PARALLEL: usize = 128;

/// The neighbours each particle's budget watches, in one flat list: particle `i`'s are
/// `list[start[i] .. start[i] + len[i]]`. An evaluation appends its particle's neighbours at
/// the end (no allocation per particle); the list is compacted, in particle order, when most
/// of it is no longer watched.
struct Watched<const D: usize> {
    start: Vec<usize>,
    len: Vec<u32>,
    list: Vec<u32>,
    /// Per entry of `list`: the neighbour's offset from the particle at the particle's
    /// evaluation, `p_j − p_i`, in units of `r` and single precision ([`stored`]).
    offsets: Vec<[f32; D]>,
    /// How many entries of `list` are watched.
    live: usize,
}

impl<const D: usize> Watched<D> {
    /// `count` particles watching nothing.
    fn new(count: usize) -> Watched<D> {
        Watched {
            start: vec![0; count],
            len: vec![0; count],
            list: Vec::new(),
            offsets: Vec::new(),
            live: 0,
        }
    }

    /// Whether particle `i` watches any neighbour.
    fn watches(&self, i: usize) -> bool {
        self.len[i] > 0
    }

    /// The neighbours particle `i` watches, and their offsets at its evaluation.
    fn of(&self, i: usize) -> (&[u32], &[[f32; D]]) {
        let range = self.start[i]..self.start[i] + self.len[i] as usize;
        (&self.list[range.clone()], &self.offsets[range])
    }

    /// Particle `i` now watches `neighbours`, at `offsets` from it.
    fn set(&mut self, i: usize, neighbours: &[u32], offsets: impl Iterator<Item = [f32; D]>) {
        self.live = self.live + neighbours.len() - self.len[i] as usize;
        self.start[i] = self.list.len();
        self.len[i] = neighbours.len() as u32;
        self.list.extend_from_slice(neighbours);
        self.offsets.extend(offsets.take(neighbours.len()));
    }

    /// No particle watches anything.
    fn clear(&mut self) {
        self.len.iter_mut().for_each(|n| *n = 0);
        self.start.iter_mut().for_each(|s| *s = 0);
        self.list.clear();
        self.offsets.clear();
        self.live = 0;
    }

    /// The lists again in particle order, when most of `list` is no longer watched.
    fn compact(&mut self) {
        if self.list.len() <= 2 * self.live + 4096 {
            return;
        }
        let mut list = Vec::with_capacity(2 * self.live);
        let mut offsets = Vec::with_capacity(2 * self.live);
        for (start, &len) in self.start.iter_mut().zip(&self.len) {
            let range = *start..*start + len as usize;
            *start = list.len();
            list.extend_from_slice(&self.list[range.clone()]);
            offsets.extend_from_slice(&self.offsets[range]);
        }
        self.list = list;
        self.offsets = offsets;
    }
}

/// Incremental `exact` detection over the time steps of one particle set (module docs).
///
/// ```
/// use boundary_core::{Domain, ParticleSet, Radius};
/// use boundary_exact::Tracker;
///
/// let rows: Vec<[f64; 2]> = (0..100).map(|k| [(k % 10) as f64, (k / 10) as f64]).collect();
/// let mut tracker = Tracker::new(Radius::new(0.8).unwrap(), Some(1), Domain::new()).unwrap();
/// let set = ParticleSet::from_rows(&rows).unwrap().to_any();
/// assert_eq!(tracker.update(&set).unwrap().boundary_count(), 36);
/// assert_eq!(tracker.recomputed(), 100);
/// // A small drift of everything: the labels stay, almost nothing is recomputed.
/// let moved: Vec<[f64; 2]> = rows.iter().map(|p| [p[0] + 0.01, p[1] - 0.005]).collect();
/// let set = ParticleSet::from_rows(&moved).unwrap().to_any();
/// assert_eq!(tracker.update(&set).unwrap().boundary_count(), 36);
/// assert!(tracker.recomputed() < 100);
/// ```
pub struct Tracker {
    r: Radius,
    /// The workers of the parallel parts; `None`: the rayon pool the tracker is called on.
    pool: Option<Arc<rayon::ThreadPool>>,
    domain: Domain,
    /// Walls as given (moved by [`Tracker::move_walls`]).
    walls: Option<AnyParticleSet>,
    /// Whether the walls moved since the last update: fixed walls cost nothing per step.
    walls_moved: bool,
    state: State,
    labels: Labels,
    /// The interface labels of the last update, with phases.
    interface: Option<Labels>,
    recomputed: usize,
    /// The ids of the last update, when it had them (and where each id was).
    ids: Option<Ids>,
}

/// Stable particle ids of one update: the list, and each id's place in it.
struct Ids {
    list: Vec<u64>,
    place: FxHashMap<u64, u32>,
}

/// Where this update's particles were at the last update.
enum Follow {
    /// Particle `k` is the last update's particle `k` (when the counts agree).
    Positional,
    /// Per particle, its index at the last update, or [`ADDED`].
    Ids(Vec<u32>),
    /// Nothing is known: every particle is evaluated.
    StartOver,
}

/// A particle that was not there at the last update (see [`Follow::Ids`]).
const ADDED: u32 = u32::MAX;

/// Where an update's large parts run: the tracker's pool, or (`None`) the rayon pool the
/// update is called on. The small parts run on the calling thread (module docs, "Threads").
#[derive(Clone, Copy)]
struct Workers<'a>(Option<&'a rayon::ThreadPool>);

impl Workers<'_> {
    /// `f` on the workers.
    fn run<R: Send>(self, f: impl FnOnce() -> R + Send) -> R {
        match self.0 {
            Some(pool) => pool.install(f),
            None => f(),
        }
    }

    /// The neighbour grid of `set` with cells of side `cell`: on the calling thread where
    /// [`NeighbourGrid::new`] sorts there, on the workers otherwise.
    fn grid<const D: usize>(
        self,
        set: &ParticleSet<D>,
        cell: f64,
    ) -> Result<NeighbourGrid<D>, CoreError> {
        if set.len() < NeighbourGrid::<D>::SORTED_IN_PARALLEL_FROM {
            NeighbourGrid::new(set, cell)
        } else {
            self.run(|| NeighbourGrid::new(set, cell))
        }
    }
}

impl std::fmt::Debug for Tracker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Tracker")
            .field("r", &self.r)
            .field("domain", &self.domain)
            .field("recomputed", &self.recomputed)
            .finish_non_exhaustive()
    }
}

enum State {
    Empty,
    D2(Track<2>),
    D3(Track<3>),
}

/// The state of the incremental path in `D` dimensions. Fluid particles are held in an order
/// of their own, the *slots*: spatial (the neighbour grid's cell order) when the tracker
/// starts over, kept from step to step whatever order the caller lists them in, particles
/// that leave taken out and arrivals appended. Neighbours then sit near each other in memory
/// at every step, and the certificates' neighbour lists stay valid when the caller reorders.
struct Track<const D: usize> {
    /// Fluid (in slot order) then wall positions of the last update; each update overwrites
    /// them in place (the walls only when they moved).
    positions: Vec<Point<D>>,
    /// Number of fluid (classified) particles.
    count: usize,
    /// Per slot: the particle's index in the caller's list at the last update.
    input_of_slot: Vec<u32>,
    /// Per fluid particle: its position at its last evaluation.
    eval: Vec<Point<D>>,
    /// Per fluid particle: its budget (length units; 0 = recompute at the next step).
    budget: Vec<f64>,
    /// Per fluid particle: the running sum `sum` at its last evaluation.
    sum_eval: Vec<f64>,
    /// Per particle, the neighbours its budget watches (slots of fluid particles, `count + w`
    /// for wall `w`): for an interior particle those whose cell proved it interior, for a
    /// boundary particle those near its witness point; empty when the budget is 0.
    watched: Watched<D>,
    /// Per particle: a bound on the largest movement of a neighbour of `watched` relative to
    /// the particle since its evaluation, proven at its last check (0 at the evaluation).
    relative: Vec<f64>,
    /// Per particle: the running sum `sum` at its last check (or evaluation).
    sum_checked: Vec<f64>,
    /// Running sum of the steps' largest displacements, rounded up.
    sum: f64,
    labels: Vec<bool>,
    /// Budgets are all 0 after a full detection: `stale` more steps run full detections,
    /// then every particle is evaluated again.
    stale: u32,
    /// The number of full detections after the next fallback: doubled at each fallback (up
    /// to [`MAX_BACKOFF`]), back to 1 after a step that recomputes few particles.
    backoff: u32,
    /// The neighbour grid of the last evaluation (fluid and walls), as sorted, kept until
    /// the particles may have drifted [`SKIN`] from there (module docs, "Reuse").
    grid: Option<NeighbourGrid<D>>,
    /// The running sum `sum` when `grid` was sorted: no particle has moved farther than
    /// `sum - grid_sum` since.
    grid_sum: f64,
}

impl Tracker {
    /// A tracker at radius `r` in `domain` (walls, solids, periodic axes, phases; module docs,
    /// "Fallbacks and scope") whose large parts run on a pool of `threads` workers of its own
    /// (`None`: on the rayon pool it is called on); the small parts run on the calling thread
    /// (module docs, "Threads").
    pub fn new(r: Radius, threads: Option<usize>, domain: Domain) -> Result<Tracker, DetectError> {
        let pool = match threads {
            None => None,
            Some(t) => Some(Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(t.max(1))
                    .build()
                    .map_err(|e| DetectError::Method {
                        method: "exact",
                        message: format!("tracker thread pool: {e}"),
                    })?,
            )),
        };
        Ok(Tracker::build(r, pool, domain))
    }

    /// A tracker at radius `r` in `domain` whose large parts run on `pool`, a pool the
    /// caller keeps (one pool for several trackers, or a pool whose workers a
    /// [`StopToken`](boundary_core::stop::StopToken) can stop).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use boundary_core::{Domain, ParticleSet, Radius};
    /// use boundary_exact::Tracker;
    ///
    /// let pool = Arc::new(rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap());
    /// let r = Radius::new(0.8).unwrap();
    /// // Two particle sets of one solver, one pool.
    /// let mut water = Tracker::with_pool(r, Arc::clone(&pool), Domain::new());
    /// let mut oil = Tracker::with_pool(r, pool, Domain::new());
    /// let rows: Vec<[f64; 2]> = (0..100).map(|k| [(k % 10) as f64, (k / 10) as f64]).collect();
    /// let set = ParticleSet::from_rows(&rows).unwrap().to_any();
    /// assert_eq!(water.update(&set).unwrap().boundary_count(), 36);
    /// assert_eq!(oil.update(&set).unwrap().boundary_count(), 36);
    /// ```
    pub fn with_pool(r: Radius, pool: Arc<rayon::ThreadPool>, domain: Domain) -> Tracker {
        Tracker::build(r, Some(pool), domain)
    }

    fn build(r: Radius, pool: Option<Arc<rayon::ThreadPool>>, domain: Domain) -> Tracker {
        let walls = domain.walls().cloned();
        Tracker {
            r,
            pool,
            domain,
            walls,
            walls_moved: false,
            state: State::Empty,
            labels: Labels::new(Vec::new()),
            interface: None,
            recomputed: 0,
            ids: None,
        }
    }

    /// How many particles the last update recomputed (all of them on a full detection).
    pub fn recomputed(&self) -> usize {
        self.recomputed
    }

    /// The labels of the last update.
    pub fn labels(&self) -> &Labels {
        &self.labels
    }

    /// The interface labels of the last update when its domain has phases
    /// ([`Tracker::set_phases`]): as [`DomainDetection::interface`](boundary_core::DomainDetection).
    pub fn interface(&self) -> Option<&Labels> {
        self.interface.as_ref()
    }

    /// The domain the updates run in (walls, solids, periodic axes, phases).
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Moves the walls: the next update sees them at these positions. The same number of walls
    /// keeps the tracker's state (their movement counts like the particles'); another number
    /// starts over.
    ///
    /// Walls equal to the current ones, bit for bit (positions and radius factors), change
    /// nothing: a solver may pass its walls at every step, and walls that did not move cost
    /// one comparison. Walls that are never moved cost nothing per step after the first
    /// update (their movement is not computed and they never trigger a re-evaluation).
    pub fn move_walls(&mut self, walls: AnyParticleSet) -> Result<(), DetectError> {
        if self.walls.as_ref() == Some(&walls) {
            return Ok(());
        }
        self.domain = std::mem::take(&mut self.domain).with_walls(walls.clone());
        self.walls = Some(walls);
        self.walls_moved = true;
        Ok(())
    }

    /// Replaces the domain: walls (as [`Tracker::move_walls`]: the same walls change nothing,
    /// moved walls keep the saving), solids, periodic axes and phases. Removing the walls
    /// starts over at the next update.
    pub fn set_domain(&mut self, domain: Domain) -> Result<(), DetectError> {
        match domain.walls() {
            Some(walls) if !walls.is_empty() => self.move_walls(walls.clone())?,
            _ => {
                if self.walls.take().is_some() {
                    self.state = State::Empty;
                }
            }
        }
        self.domain = domain;
        Ok(())
    }

    /// The phase numbers of the particles of the next updates (one per particle, in the
    /// order of [`Tracker::update`]'s set), or `None` for one phase. With phases, an update
    /// also gives the interface labels ([`Tracker::interface`]), by a full detection in the
    /// domain (module docs, "Fallbacks and scope").
    pub fn set_phases(&mut self, phases: Option<Vec<u32>>) {
        if phases.is_none() && self.domain.phases().is_none() {
            return;
        }
        self.domain = rebuild_domain(&self.domain, self.walls.clone(), phases);
    }

    /// The labels of `set`, the particles' positions at this step (same order as before),
    /// identical to a full `exact` detection of `set` in the tracker's domain.
    ///
    /// Particle `k` is taken to be the last update's particle `k`; when the count changed,
    /// the tracker starts over (every particle evaluated). Particles that come and go
    /// (inflow, outflow) keep their saving with [`Tracker::update_with_ids`].
    pub fn update(&mut self, set: &AnyParticleSet) -> Result<&Labels, DetectError> {
        self.ids = None;
        self.follow(set, Follow::Positional)
    }

    /// As [`Tracker::update`], with a stable id per particle (`ids[k]` is particle `k`'s):
    /// particles are matched to the last update's by id, in any order, so inflow (new ids) and
    /// outflow (ids that are gone) keep the saving. A new particle is evaluated; so are the
    /// interior particles whose certificate used a particle that left, and the boundary
    /// particles within `2.5r` of a new one (module docs, "Inflow and outflow"). The labels
    /// are those of a full detection of `set`, as always.
    ///
    /// After an update without ids, the tracker starts over. Fails with
    /// [`CoreError::IdsLengthMismatch`] when `ids` has another length than `set`, and
    /// [`CoreError::RepeatedId`] (naming both particles) when it repeats an id.
    ///
    /// ```
    /// use boundary_core::{Domain, ParticleSet, Radius};
    /// use boundary_exact::Tracker;
    ///
    /// let rows: Vec<[f64; 2]> = (0..100).map(|k| [(k % 10) as f64, (k / 10) as f64]).collect();
    /// let ids: Vec<u64> = (0..100).collect();
    /// let mut tracker = Tracker::new(Radius::new(0.8).unwrap(), Some(1), Domain::new()).unwrap();
    /// let set = ParticleSet::from_rows(&rows).unwrap().to_any();
    /// tracker.update_with_ids(&set, &ids).unwrap();
    /// // Outflow: the first row leaves; the other particles keep their ids.
    /// let set = ParticleSet::from_rows(&rows[10..]).unwrap().to_any();
    /// let labels = tracker.update_with_ids(&set, &ids[10..]).unwrap();
    /// assert_eq!(labels.boundary_count(), 34);
    /// // Only the particles next to the row that left were evaluated again.
    /// assert!(tracker.recomputed() < 90);
    /// ```
    pub fn update_with_ids(
        &mut self,
        set: &AnyParticleSet,
        ids: &[u64],
    ) -> Result<&Labels, DetectError> {
        if ids.len() != set.len() {
            return Err(CoreError::IdsLengthMismatch {
                particles: set.len(),
                ids: ids.len(),
            }
            .into());
        }
        let previous = self.ids.take();
        if previous.as_ref().is_some_and(|p| p.list == ids) {
            // The same particles in the same order (already checked for repeats).
            self.ids = previous;
            return self.follow(set, Follow::Positional);
        }
        let mut place = FxHashMap::with_capacity_and_hasher(ids.len(), Default::default());
        for (k, &id) in ids.iter().enumerate() {
            if let Some(first) = place.insert(id, k as u32) {
                return Err(CoreError::RepeatedId {
                    id,
                    first: first as usize,
                    second: k,
                }
                .into());
            }
        }
        let follow = match &previous {
            None => Follow::StartOver,
            Some(prev) => Follow::Ids(
                ids.iter()
                    .map(|id| prev.place.get(id).copied().unwrap_or(ADDED))
                    .collect(),
            ),
        };
        self.ids = Some(Ids {
            list: ids.to_vec(),
            place,
        });
        self.follow(set, follow)
    }

    /// One update, the particles matched to the last update's by `follow`.
    fn follow(&mut self, set: &AnyParticleSet, follow: Follow) -> Result<&Labels, DetectError> {
        if u32::try_from(set.len()).is_err() {
            return Err(CoreError::TooManyParticles(set.len()).into());
        }
        let incremental = self.domain.solids().is_empty()
            && self.domain.periodic().is_empty()
            && self.domain.phases().is_none()
            && set.radii().is_none()
            && self.walls.as_ref().is_none_or(|w| w.radii().is_none());
        if !incremental {
            let detection = match &self.pool {
                Some(pool) => pool.install(|| {
                    boundary_core::detect_in(
                        &crate::ExactDetector::default(),
                        set,
                        &self.domain,
                        self.r,
                    )
                }),
                None => boundary_core::detect_in(
                    &crate::ExactDetector::default(),
                    set,
                    &self.domain,
                    self.r,
                ),
            }?;
            self.state = State::Empty;
            self.recomputed = set.len();
            self.labels = detection.detection.labels;
            self.interface = detection.interface;
            return Ok(&self.labels);
        }
        let r = self.r;
        let walls = self.walls.as_ref();
        if let Some(w) = walls {
            if w.dim() != set.dim() {
                return Err(DetectError::Method {
                    method: "exact",
                    message: format!(
                        "tracker: the walls are {}D and the particles {}D",
                        w.dim(),
                        set.dim()
                    ),
                });
            }
        }
        let state = match follow {
            Follow::StartOver => {
                self.state = State::Empty;
                State::Empty
            }
            _ => std::mem::replace(&mut self.state, State::Empty),
        };
        let map = match &follow {
            Follow::Ids(map) => Some(map.as_slice()),
            _ => None,
        };
        let moved = self.walls_moved;
        let workers = Workers(self.pool.as_deref());
        let run = |state: State| -> Result<(State, usize), DetectError> {
            Ok(match (set, walls) {
                (AnyParticleSet::D2(s), w) => {
                    let w = match w {
                        Some(AnyParticleSet::D2(w)) => w.positions(),
                        _ => &[],
                    };
                    let old = match state {
                        State::D2(t) => Some(t),
                        _ => None,
                    };
                    let (t, n) =
                        Track::<2>::step::<Polygon>(old, map, s.positions(), w, moved, r, workers)?;
                    (State::D2(t), n)
                }
                (AnyParticleSet::D3(s), w) => {
                    let w = match w {
                        Some(AnyParticleSet::D3(w)) => w.positions(),
                        _ => &[],
                    };
                    let old = match state {
                        State::D3(t) => Some(t),
                        _ => None,
                    };
                    let (t, n) = Track::<3>::step::<Polyhedron>(
                        old,
                        map,
                        s.positions(),
                        w,
                        moved,
                        r,
                        workers,
                    )?;
                    (State::D3(t), n)
                }
            })
        };
        // On the calling thread: the step hands its large parts to the workers itself.
        let (state, recomputed) = run(state)?;
        let out = std::mem::replace(&mut self.labels, Labels::new(Vec::new())).into_vec();
        self.labels = match &state {
            State::D2(t) => Labels::new(t.input_labels(out)),
            State::D3(t) => Labels::new(t.input_labels(out)),
            State::Empty => Labels::new(Vec::new()),
        };
        self.state = state;
        self.recomputed = recomputed;
        self.walls_moved = false;
        self.interface = None;
        Ok(&self.labels)
    }
}

/// `domain` with `walls` (or none) and `phases` (or none) in place of its own.
fn rebuild_domain(
    domain: &Domain,
    walls: Option<AnyParticleSet>,
    phases: Option<Vec<u32>>,
) -> Domain {
    let mut out = Domain::new();
    if let Some(walls) = walls {
        out = out.with_walls(walls);
    }
    for &h in domain.solids().half_spaces() {
        out = out.with_solid(h);
    }
    for mesh in domain.solids().meshes() {
        out = out.with_solid_mesh(mesh.clone());
    }
    for &p in domain.periodic() {
        out = out.with_periodic(p);
    }
    if let Some(phases) = phases {
        out = out.with_phases(phases);
    }
    out
}

/// `|a − b|`.
fn dist<const D: usize>(a: &Point<D>, b: &Point<D>) -> f64 {
    (a - b).norm()
}

impl<const D: usize> Track<D> {
    /// One update: from the previous state (if it fits) to the labels of `fluid` among
    /// `fluid` and `walls`; returns the new state and the number of particles recomputed.
    fn step<C>(
        old: Option<Track<D>>,
        map: Option<&[u32]>,
        fluid: &[Point<D>],
        walls: &[Point<D>],
        walls_moved: bool,
        r: Radius,
        workers: Workers<'_>,
    ) -> Result<(Track<D>, usize), DetectError>
    where
        C: ConvexCell<D> + Default + Send + Clone,
        boundary_core::Dim<D>: boundary_core::SupportedDim,
    {
        let count = fluid.len();
        let old = match (old, map) {
            (Some(mut t), Some(map)) => {
                if t.positions.len() - t.count == walls.len() {
                    t.remap(map, fluid, r.get(), workers)?;
                    Some(t)
                } else {
                    None
                }
            }
            (old, None) => {
                old.filter(|t| t.count == count && t.positions.len() == count + walls.len())
            }
            (None, Some(_)) => None,
        };
        let Some(mut track) = old else {
            // Start over: every particle evaluated, the slots in the grid's cell order.
            let order: Vec<u32> = if count == 0 {
                Vec::new()
            } else {
                let input = ParticleSet::new(fluid.to_vec())?;
                workers
                    .grid(&input, r.get() * crate::GRID_CELL)?
                    .cell_order()
                    .to_vec()
            };
            let positions: Vec<Point<D>> = order
                .iter()
                .map(|&k| fluid[k as usize])
                .chain(walls.iter().copied())
                .collect();
            let mut track = Track {
                eval: positions[..count].to_vec(),
                positions,
                count,
                input_of_slot: order,
                budget: vec![0.0; count],
                sum_eval: vec![0.0; count],
                watched: Watched::new(count),
                relative: vec![0.0; count],
                sum_checked: vec![0.0; count],
                sum: 0.0,
                labels: vec![false; count],
                stale: 0,
                backoff: 1,
                grid: None,
                grid_sum: 0.0,
            };
            let all: Vec<usize> = (0..count).collect();
            track.evaluate::<C>(&all, r.get(), workers)?;
            return Ok((track, count));
        };
        // This step's positions over the last update's, in slot order, and the largest
        // movement, in one pass, rounded up (module docs, "Rounding"). Walls that were not
        // moved since the last update are where `positions` has them: their movement is zero,
        // not computed.
        // Below two pieces, on the calling thread.
        let in_pieces = count >= 2 * PASS_PIECE;
        let (fluid_now, walls_now) = track.positions.split_at_mut(count);
        let moved = |(p, &k): (&mut Point<D>, &u32)| {
            let now = fluid[k as usize];
            let moved = (now - *p).norm_squared();
            *p = now;
            moved
        };
        let mut largest = if in_pieces {
            workers.run(|| {
                fluid_now
                    .par_iter_mut()
                    .zip(&track.input_of_slot)
                    .with_min_len(PASS_PIECE)
                    .map(moved)
                    .reduce(|| 0.0, f64::max)
            })
        } else {
            fluid_now
                .iter_mut()
                .zip(&track.input_of_slot)
                .map(moved)
                .fold(0.0, f64::max)
        };
        if walls_moved {
            for (p, now) in walls_now.iter_mut().zip(walls) {
                largest = largest.max((now - *p).norm_squared());
                *p = *now;
            }
        }
        // `sqrt` is correctly rounded and monotone: the largest norm, bit for bit.
        let step = largest.sqrt();
        track.sum = (track.sum + step * (1.0 + ROUNDING)) * (1.0 + 4.0 * U);
        let recompute: Option<Vec<usize>> = if track.stale > 0 {
            track.stale -= 1;
            (track.stale == 0).then(|| (0..count).collect())
        } else {
            let (sum, watched, now) = (track.sum, &track.watched, &track.positions);
            let (budget, labels) = (&track.budget, &track.labels);
            let (eval, sum_eval) = (&track.eval, &track.sum_eval);
            let spent = |(i, (rel, checked)): (usize, (&mut f64, &mut f64))| {
                let spent = relative_spent(i, now, watched, rel, checked, sum, budget[i], r)
                    // Boundary: the particles away from the witness, by the movement of
                    // everything (module docs, "Boundary budget").
                    || labels[i] && {
                        let far = dist(&now[i], &eval[i]) + (sum - sum_eval[i]);
                        far * (1.0 + ROUNDING) >= far_budget(&eval[i], r.get())
                    };
                spent.then_some(i)
            };
            let (relative, checked) = (&mut track.relative, &mut track.sum_checked);
            let list: Vec<usize> = if in_pieces {
                workers.run(|| {
                    relative
                        .par_iter_mut()
                        .zip(checked)
                        .enumerate()
                        .with_min_len(PASS_PIECE)
                        .filter_map(spent)
                        .collect()
                })
            } else {
                relative
                    .iter_mut()
                    .zip(checked)
                    .enumerate()
                    .filter_map(spent)
                    .collect()
            };
            if list.len() as f64 > FULL_FRACTION * count as f64 {
                track.stale = track.backoff;
                track.backoff = (2 * track.backoff).min(MAX_BACKOFF);
                None
            } else {
                if (list.len() as f64) < 0.5 * FULL_FRACTION * count as f64 {
                    track.backoff = 1;
                }
                Some(list)
            }
        };
        let Some(recompute) = recompute else {
            let set = ParticleSet::new(std::mem::take(&mut track.positions))?;
            let detected = workers.run(|| detect_with::<D, C>(&set, count, r, 0.0));
            track.positions = set.into_positions();
            track.labels = detected?.0.labels.as_slice().to_vec();
            track.budget.iter_mut().for_each(|b| *b = 0.0);
            track.watched.clear();
            return Ok((track, count));
        };
        track.evaluate::<C>(&recompute, r.get(), workers)?;
        Ok((track, recompute.len()))
    }

    /// Follows the particles through an update with ids: `map[k]` is the caller's particle
    /// `k`'s index in the caller's list at the last update, or [`ADDED`] (module docs, "Inflow
    /// and outflow"). Slots of particles that left are taken out (the others keep their
    /// order), arrivals get slots at the end, where they are now (they have not moved).
    /// Budgets are revoked where a particle that left was in the certificate or one that came
    /// may cover the witness.
    fn remap(
        &mut self,
        map: &[u32],
        fluid: &[Point<D>],
        r: f64,
        workers: Workers<'_>,
    ) -> Result<(), DetectError>
    where
        boundary_core::Dim<D>: boundary_core::SupportedDim,
    {
        let (old_count, count) = (self.count, map.len());
        // The caller's particle at each old slot, now (ADDED: it left).
        let mut old_input_slot = vec![ADDED; old_count];
        for (s, &k) in self.input_of_slot.iter().enumerate() {
            old_input_slot[k as usize] = s as u32;
        }
        let mut now_of_slot = vec![ADDED; old_count];
        for (k, &o) in map.iter().enumerate() {
            if o != ADDED {
                now_of_slot[old_input_slot[o as usize] as usize] = k as u32;
            }
        }
        let arrivals: Vec<u32> = (0..count as u32)
            .filter(|&k| map[k as usize] == ADDED)
            .collect();
        let kept = old_count - now_of_slot.iter().filter(|&&k| k == ADDED).count();
        if kept == old_count && arrivals.is_empty() {
            // The same particles in another order: the slots stay, the grid too.
            self.input_of_slot = now_of_slot;
            return Ok(());
        }
        // Old slot to new slot (ADDED: left), in order; walls move with the fluid count.
        let mut new_slot = vec![ADDED; old_count];
        let mut next = 0u32;
        for (s, &k) in now_of_slot.iter().enumerate() {
            if k != ADDED {
                new_slot[s] = next;
                next += 1;
            }
        }
        let index = |j: u32| -> u32 {
            let j = j as usize;
            if j < old_count {
                new_slot[j]
            } else {
                (j - old_count + count) as u32
            }
        };
        let stay = |s: &usize| now_of_slot[*s] != ADDED;
        let compact = |v: &[f64], fresh: f64| -> Vec<f64> {
            (0..old_count)
                .filter(stay)
                .map(|s| v[s])
                .chain(arrivals.iter().map(|_| fresh))
                .collect()
        };
        let positions = |v: &[Point<D>]| -> Vec<Point<D>> {
            (0..old_count)
                .filter(stay)
                .map(|s| v[s])
                .chain(arrivals.iter().map(|&k| fluid[k as usize]))
                .collect()
        };
        self.eval = positions(&self.eval);
        let mut now = positions(&self.positions);
        now.extend_from_slice(&self.positions[old_count..]);
        self.positions = now;
        // Watched neighbours renumbered, in the new slot order. An interior certificate that
        // used a particle that left is revoked (evaluated again); a boundary particle's witness
        // only loses a particle that could have covered it, which is dropped from the list.
        let mut watched = Watched::new(count);
        let mut renumbered = Vec::new();
        for (s, &k) in now_of_slot.iter().enumerate() {
            if k == ADDED {
                continue;
            }
            let slot = new_slot[s] as usize;
            let (list, offsets) = self.watched.of(s);
            renumbered.clear();
            renumbered.extend(
                list.iter()
                    .zip(offsets)
                    .map(|(&j, q)| (index(j), *q))
                    .filter(|(j, _)| *j != ADDED),
            );
            if renumbered.len() < list.len() && !self.labels[s] {
                self.budget[s] = 0.0;
            } else {
                let (list, offsets): (Vec<u32>, Vec<[f32; D]>) = renumbered.iter().copied().unzip();
                watched.set(slot, &list, offsets.into_iter());
            }
        }
        self.watched = watched;
        self.budget = compact(&self.budget, 0.0);
        self.sum_eval = compact(&self.sum_eval, self.sum);
        self.relative = compact(&self.relative, 0.0);
        self.sum_checked = compact(&self.sum_checked, self.sum);
        self.labels = (0..old_count)
            .filter(stay)
            .map(|s| self.labels[s])
            .chain(arrivals.iter().map(|_| false))
            .collect();
        self.input_of_slot = now_of_slot
            .into_iter()
            .filter(|&k| k != ADDED)
            .chain(arrivals.iter().copied())
            .collect();
        self.count = count;
        // The grid indexes the old slots.
        self.grid = None;
        // Boundary particles: a new particle within `(1 + WITNESS_REACH)·r` of the evaluation
        // position may be near the witness (interior certificates are untouched by more
        // particles).
        if !arrivals.is_empty() {
            let added = ParticleSet::new(arrivals.iter().map(|&k| fluid[k as usize]).collect())?;
            let reach = ((1.0 + WITNESS_REACH) * r) * (1.0 + ROUNDING);
            let grid = workers.grid(&added, reach)?;
            let (budget, labels, eval) = (&mut self.budget, &self.labels, &self.eval);
            let revoke = |((b, &boundary), e): ((&mut f64, &bool), &Point<D>)| {
                if *b > 0.0 && boundary {
                    // Grown by ROUNDING for the rounding of the distances and of `e`'s
                    // witness point.
                    let reach = reach + witness_rounding(e, r);
                    let mut near = false;
                    grid.for_each_within(e, reach, |_, _| near = true);
                    if near {
                        *b = 0.0;
                    }
                }
            };
            if count >= 2 * PASS_PIECE {
                workers.run(|| {
                    budget
                        .par_iter_mut()
                        .zip(labels)
                        .zip(eval)
                        .with_min_len(PASS_PIECE)
                        .for_each(revoke)
                });
            } else {
                budget.iter_mut().zip(labels).zip(eval).for_each(revoke);
            }
        }
        Ok(())
    }

    /// The labels in the caller's order of the last update, in `out`'s memory.
    fn input_labels(&self, mut out: Vec<bool>) -> Vec<bool> {
        out.clear();
        out.resize(self.count, false);
        for (&k, &label) in self.input_of_slot.iter().zip(&self.labels) {
            out[k as usize] = label;
        }
        out
    }

    /// Evaluates the fluid particles `which` (ascending) at `positions`: their labels and
    /// budgets.
    fn evaluate<C>(
        &mut self,
        which: &[usize],
        r: f64,
        workers: Workers<'_>,
    ) -> Result<(), DetectError>
    where
        C: ConvexCell<D> + Default + Send + Clone,
        boundary_core::Dim<D>: boundary_core::SupportedDim,
    {
        if which.is_empty() {
            return Ok(());
        }
        let positions = std::mem::take(&mut self.positions);
        let evaluated = self.evaluate_in::<C>(&positions, which, r, workers);
        self.positions = positions;
        evaluated
    }

    fn evaluate_in<C>(
        &mut self,
        positions: &[Point<D>],
        which: &[usize],
        r: f64,
        workers: Workers<'_>,
    ) -> Result<(), DetectError>
    where
        C: ConvexCell<D> + Default + Send + Clone,
        boundary_core::Dim<D>: boundary_core::SupportedDim,
    {
        // The last grid as it was sorted, while the particles may have drifted less than the
        // skin from there: its queries reach `drift` farther and are tested at the current
        // positions (`Within`). The drift is bounded by the running sum's growth since
        // (each step adds its largest displacement, rounded up), grown for the subtraction.
        let drift = (self.sum - self.grid_sum) * (1.0 + ROUNDING);
        let (grid, drift) = match self.grid.take() {
            Some(grid) if grid.cell_order().len() == positions.len() && drift <= SKIN * r => {
                (grid, drift)
            }
            _ => {
                self.grid_sum = self.sum;
                let set = ParticleSet::new(positions.to_vec())?;
                (workers.grid(&set, r * crate::GRID_CELL)?, 0.0)
            }
        };
        let within = Within {
            grid: &grid,
            positions,
            drift,
        };
        // Per piece: (particle, label, budget, how many neighbours it watches), and those
        // neighbours one after the other.
        type Piece = (Vec<(usize, bool, f64, u32)>, Vec<u32>);
        let start = || (Scratch::<D, C>::default(), Vec::new(), Vec::new());
        let one = |(mut scratch, mut results, mut watched): (Scratch<D, C>, Vec<_>, Vec<u32>),
                   &i: &usize| {
            let before = watched.len();
            let (label, budget) = evaluate_one(&within, i, r, &mut scratch, &mut watched);
            results.push((i, label, budget, (watched.len() - before) as u32));
            (scratch, results, watched)
        };
        let pieces: Vec<Piece> = if which.len() < EVALUATION_PARALLEL {
            let (_, results, watched) = which.iter().fold(start(), one);
            vec![(results, watched)]
        } else {
            workers.run(|| {
                which
                    .par_iter()
                    .with_min_len(EVALUATION_PIECE)
                    .fold(start, one)
                    .map(|(_, results, watched)| (results, watched))
                    .collect()
            })
        };
        for (results, watched) in pieces {
            let mut at = 0;
            for (i, label, budget, len) in results {
                let len = len as usize;
                self.labels[i] = label;
                self.budget[i] = budget;
                let neighbours = &watched[at..at + len];
                let p = positions[i];
                let offsets = neighbours
                    .iter()
                    .map(|&j| stored(positions[j as usize] - p, r));
                self.watched.set(i, neighbours, offsets);
                at += len;
                self.relative[i] = 0.0;
                self.sum_checked[i] = self.sum;
                self.eval[i] = positions[i];
                self.sum_eval[i] = self.sum;
            }
        }
        self.watched.compact();
        self.grid = Some(grid);
        Ok(())
    }
}

/// Neighbour queries at the current positions over a grid sorted at earlier ones (module
/// docs, "Reuse"). The grid was built over `positions` (fluid slots, then walls), so its
/// indices are theirs; no particle is farther than `drift` from where the grid sorted it. A
/// query reaches `drift` farther on the grid (and `1e-9` relative, for the rounding of the
/// distances the grid tests) and tests each particle it finds again at its current position.
struct Within<'a, const D: usize> {
    grid: &'a NeighbourGrid<D>,
    positions: &'a [Point<D>],
    drift: f64,
}

impl<const D: usize> Within<'_, D> {
    /// Calls `f(j, d2)` for every particle `j` within `radius` of `q` now (`d2` its squared
    /// distance now), as [`NeighbourGrid::for_each_within`] would on a grid of the current
    /// positions.
    fn for_each(&self, q: &Point<D>, radius: f64, mut f: impl FnMut(usize, f64)) {
        if self.drift == 0.0 {
            // Sorted at the current positions.
            self.grid.for_each_within(q, radius, f);
            return;
        }
        let r2 = radius * radius;
        let reach = radius * (1.0 + 1e-9) + self.drift;
        self.grid.for_each_within(q, reach, |j, _| {
            let d2 = (self.positions[j] - q).norm_squared();
            if d2 <= r2 {
                f(j, d2);
            }
        });
    }

    /// Appends every particle within `radius` of `q` now as a [`Near`] entry `(d2, j, j)`
    /// (`j` indexes `positions`).
    fn gather(&self, q: &Point<D>, radius: f64, out: &mut Vec<Near>) {
        self.for_each(q, radius, |j, d2| {
            out.push((d2.to_bits(), j as u32, j as u32));
        });
    }
}

/// The label of particle `i` and its budget (module docs); the neighbours its budget watches
/// (an interior particle's cell's, a boundary particle's witness's) are pushed on `watched`
/// when the budget is positive.
fn evaluate_one<const D: usize, C: ConvexCell<D> + Clone>(
    within: &Within<'_, D>,
    i: usize,
    r: f64,
    scratch: &mut Scratch<D, C>,
    watched: &mut Vec<u32>,
) -> (bool, f64) {
    let positions = within.positions;
    let p = positions[i];
    // The neighbours within FIRST_REACH·r first; the cell gathers the rest (up to 2r) when
    // it reaches beyond half of that (every other bisector lies farther).
    scratch.near.clear();
    within.gather(&p, FIRST_REACH * r, &mut scratch.near);
    // `i` itself has d2 = 0; any other zero is an exact duplicate (module docs).
    let duplicated = scratch.near.iter().filter(|x| x.0 == 0).count() > 1;
    scratch.near.retain(|x| x.0 != 0);
    scratch.beyond = 0.5 * FIRST_REACH * (1.0 - 1e-9);
    let gather_all = |list: &mut Vec<Near>| {
        list.clear();
        within.gather(&p, 2.0 * r * (1.0 + NEAR_SLACK), list);
        list.retain(|x| x.0 != 0);
    };

    // The float cell, clipped to the end; the fast cell first where there is one.
    let mut decided = None;
    if C::HAS_FAST {
        let near = Neighbours {
            list: &mut scratch.near,
            beyond: &mut scratch.beyond,
            gather_all: &gather_all,
        };
        let cell = cell_margin(&p, positions, r, near, &mut scratch.fast, true, false);
        if !cell.degenerate && cell.margin.abs() > cell.tau {
            decided = Some((cell, scratch.fast.farthest()));
        }
    }
    if decided.is_none() {
        let near = Neighbours {
            list: &mut scratch.near,
            beyond: &mut scratch.beyond,
            gather_all: &gather_all,
        };
        let cell = cell_margin(&p, positions, r, near, &mut scratch.cell, false, false);
        if !cell.degenerate && cell.margin.abs() > cell.tau {
            decided = Some((cell, scratch.cell.farthest()));
        }
    }
    let Some((cell, far)) = decided else {
        // Certificates and the exact predicate: the label of a full detection, no budget.
        let (_, label, _) = classify(&p, positions, r, 0.0, scratch, &gather_all);
        return (label, 0.0);
    };
    let boundary = cell.margin > 0.0;
    if duplicated {
        return (boundary, 0.0);
    }
    // The nearest neighbour, first of the sorted list (or `2r`, if none is within it), caps
    // the interior budget.
    let m = match scratch.near.first() {
        Some(x) if cell.used > 0 => f64::from_bits(x.0).sqrt().min(2.0 * r),
        _ => 2.0 * r,
    };
    if !boundary {
        // Interior: b = m²(r − ρ)/(2rρ), ρ = (1 + margin + τ)·r, over the neighbours the cell
        // took (the first `used` of the sorted list).
        let rho = 1.0 + cell.margin + cell.tau;
        if rho >= 1.0 || cell.used == 0 {
            return (false, 0.0);
        }
        let mh = m / r;
        let budget = r * mh * mh * (1.0 - rho) / (2.0 * rho);
        watched.extend(scratch.near[..cell.used].iter().map(|x| x.1));
        return (false, budget.min(m) * (1.0 - ROUNDING));
    }
    // Boundary: the witness x on S_i toward the farthest vertex, and the particles within
    // WITNESS_REACH·r of it, which its budget watches (the others count as far).
    let norm = far.iter().map(|a| a * a).sum::<f64>().sqrt();
    let x = Point::<D>::from_fn(|k, _| p[k] + r * (far[k] / norm));
    let mut d2min = (WITNESS_REACH * r).powi(2);
    let before = watched.len();
    within.for_each(&x, WITNESS_REACH * r, |j, d2| {
        if j != i {
            d2min = d2min.min(d2);
            watched.push(j as u32);
        }
    });
    let budget = d2min.sqrt() - r - witness_rounding(&p, r);
    if budget <= 0.0 {
        watched.truncate(before);
        return (true, 0.0);
    }
    (true, budget * (1.0 - ROUNDING))
}

/// Whether particle `i`'s budget is spent by the movement of the neighbours it watches
/// relative to it since its evaluation (module docs, "Bookkeeping"). `relative` bounds that
/// movement as of the last check, when the running sum was `checked`: since then it grew by
/// at most twice the sum's growth, and while that bound stays within the budget the
/// neighbours are not read. Otherwise the movement is measured, from the offsets at the
/// evaluation, and `relative` and `checked` are updated.
#[allow(clippy::too_many_arguments)] // one particle's bookkeeping, called in the step's pass
#[inline(always)] // called for every particle at every step: the call cost more than the test
fn relative_spent<const D: usize>(
    i: usize,
    now: &[Point<D>],
    watched: &Watched<D>,
    relative: &mut f64,
    checked: &mut f64,
    sum: f64,
    budget: f64,
    r: Radius,
) -> bool {
    if !watched.watches(i) {
        // A budget of 0, or one that watches no neighbour.
        return *relative * (1.0 + ROUNDING) >= budget;
    }
    let bound = (*relative + 2.0 * (sum - *checked) * (1.0 + ROUNDING)) * (1.0 + ROUNDING);
    if bound < budget {
        return false;
    }
    let (list, offsets) = watched.of(i);
    let p = now[i];
    // The largest squared norm, then one square root: `sqrt` is correctly rounded and
    // monotone, so this is the largest of the norms, bit for bit. Written out per axis, the
    // stored offset read back as `stored·r`; the positions are finite, so a plain comparison
    // takes the largest.
    let mut most2 = 0.0f64;
    let r_len = r.get();
    for (&j, q) in list.iter().zip(offsets) {
        let nj = &now[j as usize];
        let mut d2 = 0.0;
        for k in 0..D {
            let d = (nj[k] - p[k]) - f64::from(q[k]) * r_len;
            d2 += d * d;
        }
        most2 = if d2 > most2 { d2 } else { most2 };
    }
    let most = most2.sqrt();
    // `64u·(r + most)` covers the rounding of the differences, `OFFSET_STORAGE·r` that of the
    // offsets to single precision (module docs, "Rounding").
    *relative = (most * (1.0 + ROUNDING) + 64.0 * U * (r.get() + most) + OFFSET_STORAGE * r.get())
        * (1.0 + ROUNDING);
    *checked = sum;
    *relative * (1.0 + ROUNDING) >= budget
}

/// A watched neighbour's offset `q = p_j − p_i` as stored: `q/r`, each coordinate rounded to
/// single precision (half the memory the step's checks read); read back as `stored·r`.
fn stored<const D: usize>(q: Point<D>, r: f64) -> [f32; D] {
    std::array::from_fn(|k| (q[k] / r) as f32)
}

/// What storing an offset may move it, in units of `r`: an offset is within `2.5r` of zero
/// (the witness's neighbours lie within `1.5r` of a point at `r`; a cell's within
/// `2r(1 + NEAR_SLACK)`), so each stored coordinate is within 2.5 and moves at most
/// `2.5·2^-24` (or `2^-150` if subnormal) plus the few `u` of the division and of the product
/// that reads it back; the offset moves at most `√3·2.5r·(2^-24 + 4u) < 2.6e-7·r`.
const OFFSET_STORAGE: f64 = 3e-7;

/// What the witness point loses to its own rounding: its distance from `S_i` is below
/// `4u·(r + √D·|p_i|_∞)` (module docs, "Rounding").
fn witness_rounding<const D: usize>(p: &Point<D>, r: f64) -> f64 {
    let pmax = p.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    1e-12 * r + 1e-14 * pmax
}

/// A boundary particle's far budget: every particle farther than `WITNESS_REACH·r` from its
/// witness point must close the gap to `r` (module docs, "Boundary budget"); `eval` is the
/// particle's position at its evaluation.
fn far_budget<const D: usize>(eval: &Point<D>, r: f64) -> f64 {
    ((WITNESS_REACH - 1.0) * r - witness_rounding(eval, r)) * (1.0 - ROUNDING)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lists replaced many times read back as last set, before and after compaction, which
    /// keeps every list and drops the dead entries.
    #[test]
    fn watched_lists_survive_replacement_and_compaction() {
        let count = 300;
        let mut watched = Watched::<2>::new(count);
        let list = |i: usize, round: u32| -> Vec<u32> {
            (0..(i as u32 + round) % 7)
                .map(|k| k * 1000 + i as u32 + round)
                .collect()
        };
        // Whole numbers below 2^24: stored exactly in single precision.
        let offset = |j: u32| stored(Point::<2>::new(f64::from(j), -f64::from(j)), 1.0);
        for round in 0..40 {
            for i in (0..count).filter(|i| !(i + round as usize).is_multiple_of(3)) {
                let l = list(i, round);
                watched.set(i, &l, l.iter().map(|&j| offset(j)));
            }
        }
        let expected = |i: usize| -> Vec<u32> {
            let round = (0..40u32)
                .rev()
                .find(|r| !(i + *r as usize).is_multiple_of(3))
                .unwrap();
            list(i, round)
        };
        let check = |watched: &Watched<2>| {
            for i in 0..count {
                let (l, q) = watched.of(i);
                assert_eq!(l, expected(i).as_slice(), "particle {i}");
                assert!(
                    l.iter().zip(q).all(|(&j, q)| *q == offset(j)),
                    "particle {i}"
                );
            }
        };
        check(&watched);
        let live: usize = (0..count).map(|i| expected(i).len()).sum();
        assert_eq!(watched.live, live);
        assert!(
            watched.list.len() > 2 * live + 4096,
            "{}",
            watched.list.len()
        );
        watched.compact();
        assert_eq!(watched.list.len(), live);
        assert_eq!(watched.offsets.len(), live);
        check(&watched);
        watched.clear();
        assert!((0..count).all(|i| watched.of(i).0.is_empty()));
    }
}
