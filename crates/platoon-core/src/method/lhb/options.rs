//! Layered hit buffers' options: plain data the tracer turns into buffers, push words and the
//! kernels' constants.

use super::directions::DirectionSet;

/// How the buffers' lists are built (the thesis' two rasterizers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RasterVariant {
    /// One pass appending into lists of a fixed capacity; layers past it are lost and counted.
    #[default]
    Capacity,
    /// A counting pass, a prefix sum and a filling pass: every layer kept, no capacity.
    Exact,
}

impl RasterVariant {
    pub fn name(self) -> &'static str {
        match self {
            RasterVariant::Capacity => "capacity",
            RasterVariant::Exact => "exact",
        }
    }

    pub fn parse(s: &str) -> Result<RasterVariant, String> {
        match s {
            "capacity" => Ok(RasterVariant::Capacity),
            "exact" => Ok(RasterVariant::Exact),
            _ => Err(format!(
                "unknown rasterizer variant {s:?}: capacity (fixed lists, overflow lost) or \
                 exact (count, prefix sum, fill)"
            )),
        }
    }
}

/// How layered hit buffers render a frame. The defaults are the thesis' results: 320
/// icosahedral directions, 128 x 128 texels, 16 layers, a cone of one texel, two bounces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LhbOptions {
    pub directions: DirectionSet,
    /// Texels on a side of every buffer.
    pub resolution: u32,
    /// Layers a texel keeps (the capacity variant).
    pub layers: u32,
    /// Radius of the cone jitter, in texels (0: every lookup from the texel of its origin).
    pub cone: f32,
    /// Indirect bounces answered by lookups after the first diffuse vertex.
    pub bounces: u32,
    pub variant: RasterVariant,
    /// Rebuild every buffer every frame. Otherwise (the thesis' scheme, capacity rasterizer) a
    /// device keeps the layers of the instances that have not moved and rasterizes only the
    /// others again (the same lists while nothing overflows).
    pub rebuild: bool,
}

impl Default for LhbOptions {
    fn default() -> Self {
        LhbOptions {
            directions: DirectionSet::default(),
            resolution: 128,
            layers: 16,
            cone: 1.0,
            bounces: 2,
            variant: RasterVariant::Capacity,
            rebuild: false,
        }
    }
}

/// The most lookup bounces (the thesis measures 1-5).
pub const MAX_BOUNCES: u32 = 5;
/// The largest buffer side: a row of texels is one thread's loop in the prefix sum, which
/// llvmpipe's loop limit (65535 iterations an invocation) allows many times over.
pub const MAX_RESOLUTION: u32 = 1024;
/// The most bytes the buffers may take (lists and counts, every direction).
pub const MAX_BYTES: u64 = 4 << 30;
/// The buffers' frame: the scene's bounding sphere grown by this fraction of its radius.
pub const FRAME_MARGIN: f32 = 0.05;

impl LhbOptions {
    /// Texels of every direction together.
    pub fn texels(&self) -> u64 {
        self.directions.count() as u64 * self.resolution as u64 * self.resolution as u64
    }

    /// Bytes of the capacity variant's lists and counts (the exact variant's lists take what
    /// the scene needs, known after its counting pass).
    pub fn capacity_bytes(&self) -> u64 {
        self.texels() * (4 + 8 * self.layers as u64)
    }

    /// What is wrong with the options, if anything.
    pub fn validate(&self) -> Result<(), String> {
        if !(8..=MAX_RESOLUTION).contains(&self.resolution) {
            return Err(format!(
                "the buffers' resolution must be in 8..={MAX_RESOLUTION}, not {}",
                self.resolution
            ));
        }
        if !(1..=64).contains(&self.layers) {
            return Err(format!(
                "layers per texel must be in 1..=64, not {}",
                self.layers
            ));
        }
        if !(self.cone >= 0.0 && self.cone <= 64.0) {
            return Err(format!(
                "the cone radius must be in 0..=64 texels, not {}",
                self.cone
            ));
        }
        if !(1..=MAX_BOUNCES).contains(&self.bounces) {
            return Err(format!(
                "lookup bounces must be in 1..={MAX_BOUNCES}, not {}",
                self.bounces
            ));
        }
        if self.variant == RasterVariant::Capacity && self.capacity_bytes() > MAX_BYTES {
            return Err(format!(
                "{} directions of {}^2 texels x {} layers take {:.1} GiB, more than the {} GiB \
                 allowed: fewer directions, a lower resolution or fewer layers",
                self.directions.count(),
                self.resolution,
                self.layers,
                self.capacity_bytes() as f64 / (1u64 << 30) as f64,
                MAX_BYTES >> 30
            ));
        }
        Ok(())
    }

    /// The biased parts, for the output's list of approximations.
    pub fn approximations(&self) -> Vec<String> {
        let mut a = vec![
            format!(
                "layered hit buffers: indirect rays after the first diffuse vertex ({} bounces) \
                 answered by the buffer of the nearest of {} directions ({}) at {}^2 texels, a \
                 cone jitter of {} texels; light reflected more often is lost",
                self.bounces,
                self.directions.count(),
                self.directions,
                self.resolution,
                self.cone
            ),
            "layered hit buffers: surfaces are one-sided (a lookup skips the backs the ray \
             would meet); a lookup's hit lies on its texel's centre line, not on the ray"
                .into(),
        ];
        if self.variant == RasterVariant::Capacity {
            a.push(format!(
                "layered hit buffers: {} layers per texel; layers past them are lost \
                 (lhb_build reports how many)",
                self.layers
            ));
        }
        a
    }
}
