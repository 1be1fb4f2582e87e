//! IGI's options: plain data the tracer turns into kernel defines and push constants, and the
//! gather grid they imply (mirrored by shaders/igi/pixel.glsl).

/// How IGI renders a frame. The defaults are the exact method: every pixel gathers every VPL
/// through exact visibility with the unbounded geometry term (consistent: it converges to the
/// path tracer's indirect diffuse light as the VPLs grow in number).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IgiOptions {
    /// Particle paths shot from the lights per frame (picked by power, Halton-distributed).
    pub paths: u32,
    /// VPLs a path leaves at most (one per diffuse hit): light that bounced more often is lost.
    pub bounces: u32,
    /// The bounded geometry term's minimum distance: 1/d^2 is blended into 1/d_min^2 by a
    /// smoothstep between 0.8 and 1.2 d_min (biased: light near a VPL is lost). 0: unbounded.
    pub min_distance: f32,
    /// VPL shadow rays stop at the boxes of BVH leaves instead of their triangles (biased).
    pub imperfect_visibility: bool,
    /// Indirect light gathered at one pixel in k x k and upsampled by a joint bilateral filter
    /// guided by full-resolution normals and depths (1: every pixel gathers).
    pub downsample: u32,
    /// VPLs split into m x n subsets, one per pixel of each m x n tile (of gather pixels),
    /// recombined by a discontinuity buffer ([1, 1]: every gather pixel sees every VPL).
    pub interleave: [u32; 2],
}

impl Default for IgiOptions {
    fn default() -> Self {
        IgiOptions {
            paths: 64,
            bounces: 3,
            min_distance: 0.0,
            imperfect_visibility: false,
            downsample: 1,
            interleave: [1, 1],
        }
    }
}

/// The most VPLs one light path may leave (the Halton dimensions the kernel has).
pub const MAX_BOUNCES: u32 = 8;

/// Thresholds of the filters: neighbours whose depth differs by more than this fraction of the
/// pixel's, or whose normal is further than this cosine, are other surfaces.
pub const DEPTH_THRESHOLD: f32 = 0.1;
pub const NORMAL_THRESHOLD: f32 = 0.9;

impl IgiOptions {
    /// With `vpls` VPL slots (paths x bounces, the count the paper quotes) and the rest default.
    pub fn with_vpls(vpls: u32) -> IgiOptions {
        let d = IgiOptions::default();
        IgiOptions {
            paths: vpls.div_ceil(d.bounces).max(1),
            ..d
        }
    }

    /// VPL slots the kernel allocates: one per path and bounce (empty where a path ended).
    pub fn slots(&self) -> u32 {
        self.paths * self.bounces
    }

    /// The gather writes irradiance and a G-buffer for a filter to finish after assembly.
    pub fn filtered(&self) -> bool {
        self.downsample > 1 || self.interleave != [1, 1]
    }

    /// Pixels per interleaving tile: the VPL subsets.
    pub fn subsets(&self) -> u32 {
        self.interleave[0] * self.interleave[1]
    }

    /// What is wrong with the options, if anything.
    pub fn validate(&self) -> Result<(), String> {
        if self.paths == 0 {
            return Err("IGI needs at least one light path".into());
        }
        if !(1..=MAX_BOUNCES).contains(&self.bounces) {
            return Err(format!(
                "IGI VPL bounces must be in 1..={MAX_BOUNCES}, not {}",
                self.bounces
            ));
        }
        if self.slots() > 1 << 20 {
            return Err(format!(
                "{} VPLs per frame is more than the 2^20 the kernel takes",
                self.slots()
            ));
        }
        if !(self.min_distance >= 0.0 && self.min_distance.is_finite()) {
            return Err("the IGI minimum distance must be finite and >= 0".into());
        }
        if !(1..=16).contains(&self.downsample) {
            return Err(format!(
                "IGI downsampling must be in 1..=16, not {}",
                self.downsample
            ));
        }
        if self.interleave.iter().any(|&m| !(1..=8).contains(&m)) {
            return Err(format!(
                "IGI interleaving tiles must be 1..=8 on a side, not {}x{}",
                self.interleave[0], self.interleave[1]
            ));
        }
        Ok(())
    }

    /// The biased parts, for the output's list of approximations.
    pub fn approximations(&self) -> Vec<String> {
        let mut a = vec![format!(
            "instant global illumination: indirect diffuse light from {} VPLs per frame ({} \
             paths, light after {} bounces lost; light reflected by glossy surfaces onto diffuse \
             ones lost; a VPL's diffuse albedo takes Fresnel at its incoming direction)",
            self.slots(),
            self.paths,
            self.bounces
        )];
        if self.min_distance > 0.0 {
            a.push(format!(
                "VPL geometry term bounded at a minimum distance of {}",
                self.min_distance
            ));
        }
        if self.imperfect_visibility {
            a.push("VPL shadow rays against BVH leaf boxes (imperfect visibility)".into());
        }
        if self.downsample > 1 {
            let k = self.downsample;
            a.push(format!(
                "indirect light gathered at 1/{k} x 1/{k} resolution, joint bilateral upsampling"
            ));
        }
        if self.interleave != [1, 1] {
            a.push(format!(
                "interleaved sampling over {}x{} VPL subsets with a discontinuity buffer",
                self.interleave[0], self.interleave[1]
            ));
        }
        a
    }

    /// The gather grid: the pixels that gather indirect light, one per k x k cell, at the
    /// cell's centre (the last cell's clamped into the frame). Mirrors shaders/igi/pixel.glsl.
    pub fn grid(&self, width: u32, height: u32) -> Grid {
        Grid {
            k: self.downsample.max(1),
            width,
            height,
        }
    }
}

/// The pixels that gather, one per k x k cell (see `IgiOptions::grid`).
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    pub k: u32,
    pub width: u32,
    pub height: u32,
}

impl Grid {
    pub fn cells(&self) -> (u32, u32) {
        (self.width.div_ceil(self.k), self.height.div_ceil(self.k))
    }
    /// The pixel that gathers for cell (i, j).
    pub fn pixel(&self, i: u32, j: u32) -> (u32, u32) {
        let at = |c: u32, n: u32| (c * self.k + self.k / 2).min(n - 1);
        (at(i, self.width), at(j, self.height))
    }
}
