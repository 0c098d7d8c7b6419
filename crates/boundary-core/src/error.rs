use thiserror::Error;

/// Errors raised while building core values from user input.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum CoreError {
    /// A coordinate is NaN or infinite.
    #[error("particle {index}: coordinate {axis} is not finite ({value})")]
    NonFiniteCoordinate {
        /// Index of the particle in input order.
        index: usize,
        /// Axis (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The offending value.
        value: f64,
    },
    /// The resolution is not a positive finite number.
    #[error("radius must be positive and finite, got {0}")]
    InvalidRadius(f64),
    /// A particle spacing is not a positive finite number.
    #[error("particle spacing must be positive and finite, got {0}")]
    InvalidSpacing(f64),
    /// The resolution lies outside [`crate::Radius::MIN`]`..=`[`crate::Radius::MAX`].
    #[error(
        "radius {0:e} is outside the supported range 1e-100..=1e100 (squared distances of \
         up to 4r² must stay normal floating-point numbers); rescale the coordinates"
    )]
    RadiusOutOfRange(f64),
    /// A per-particle radius is not a positive finite number.
    #[error("particle {index}: radius must be positive and finite, got {value}")]
    InvalidParticleRadius {
        /// Index of the particle in input order.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A per-particle radius (after scaling by `r`) lies outside
    /// [`crate::Radius::MIN`]`..=`[`crate::Radius::MAX`].
    #[error("particle {index}: radius {value:e} is outside the supported range 1e-100..=1e100")]
    ParticleRadiusOutOfRange {
        /// Index of the particle in input order.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// The radii do not match the particles one to one.
    #[error("{radii} radii for {particles} particles (one radius per particle)")]
    RadiiLengthMismatch {
        /// Number of particles.
        particles: usize,
        /// Number of radii given.
        radii: usize,
    },
    /// The particle ids do not match the particles one to one.
    #[error("{ids} ids for {particles} particles (one id per particle)")]
    IdsLengthMismatch {
        /// Number of particles.
        particles: usize,
        /// Number of ids given.
        ids: usize,
    },
    /// Two particles carry the same id.
    #[error("id {id} is given to particles {first} and {second} (ids must be unique)")]
    RepeatedId {
        /// The id.
        id: u64,
        /// The first particle with it.
        first: usize,
        /// The next one.
        second: usize,
    },
    /// Particles moved in a neighbour grid that indexes another number of them.
    #[error("neighbour grid: it indexes {indexed} particles, {given} positions given")]
    GridLengthMismatch {
        /// Particles in the grid.
        indexed: usize,
        /// Positions given.
        given: usize,
    },
    /// The neighbour grid cannot index this scene at this cell size.
    #[error("neighbour grid: extent {extent:e} is too large for cell size {cell:e}")]
    GridTooFine {
        /// Largest extent of the bounding box.
        extent: f64,
        /// Requested cell size.
        cell: f64,
    },
    /// Two label vectors that should describe the same particles differ in length.
    #[error("label vectors differ in length: {predicted} predicted, {truth} reference")]
    LengthMismatch {
        /// Length of the predicted labels.
        predicted: usize,
        /// Length of the reference labels.
        truth: usize,
    },
    /// The index space of the particle set is exhausted (more than `u32::MAX` particles).
    #[error("too many particles: {0} (at most {max})", max = u32::MAX)]
    TooManyParticles(usize),
    /// A decomposition's owner assignment does not fit its particle set or part count.
    #[error("decomposition: {0}")]
    InvalidDecomposition(String),
}
