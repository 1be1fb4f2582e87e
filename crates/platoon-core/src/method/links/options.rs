//! The options of vertex links: plain data the facade's update and the tracer read.

/// How vertex links light a frame. The defaults are the paper's (256 directions, three bounces)
/// with smoothing across a 30 degree feature angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinksOptions {
    /// Directions every element shoots (n_C): a square of at least 4 (16, 64, 256, 1024).
    pub directions: u32,
    /// Bounces the gather carries (n_B): light reflected more often is lost.
    pub bounces: u32,
    /// Vertices of a mesh at one position whose normals are within this angle (degrees) are one
    /// element, and smoothing averages an element only with neighbours within it.
    pub feature_angle: f32,
    /// The paper's smoothing of the gathered light over each element's one-ring.
    pub smooth: bool,
    /// Next-event samples of the direct light at each element (every light kind).
    pub light_samples: u32,
    /// The direct light at an element averaged over its fan (the triangles around it) with
    /// the weight its interpolation gives it there, instead of taken at its position alone:
    /// the continuous form of the paper's light links' oversampling (a 1:4 subdivision of the
    /// one-ring), against the aliasing of light that varies within a triangle.
    pub fan_light: bool,
    /// Keep every ray's hit (16 bytes a ray) so that an update after geometry moved shoots
    /// again only the rays that can have changed (platoon's revalidation, the same bits as
    /// shooting them all); off: the paper's regeneration of every link.
    pub revalidate: bool,
}

impl Default for LinksOptions {
    fn default() -> Self {
        LinksOptions {
            directions: 256,
            bounces: 3,
            feature_angle: 30.0,
            smooth: true,
            light_samples: 64,
            fan_light: true,
            revalidate: true,
        }
    }
}

/// The most directions an element shoots (a 64 x 64 square).
pub const MAX_DIRECTIONS: u32 = 4096;
/// The most bounces the gather carries (each is a pass over every link).
pub const MAX_BOUNCES: u32 = 16;

impl LinksOptions {
    /// What is wrong with the options, if anything.
    pub fn validate(&self) -> Result<(), String> {
        if self.directions > MAX_DIRECTIONS {
            return Err(format!(
                "links: at most {MAX_DIRECTIONS} directions per element, not {}",
                self.directions
            ));
        }
        super::directions::directions(self.directions).map_err(|e| e.to_string())?;
        if !(1..=MAX_BOUNCES).contains(&self.bounces) {
            return Err(format!(
                "links: bounces must be in 1..={MAX_BOUNCES}, not {}",
                self.bounces
            ));
        }
        if !(self.feature_angle > 0.0 && self.feature_angle <= 180.0) {
            return Err(format!(
                "links: the feature angle must be in (0, 180] degrees, not {}",
                self.feature_angle
            ));
        }
        if self.light_samples == 0 {
            return Err("links: at least one light sample per element".into());
        }
        Ok(())
    }

    /// The cosine of the feature angle: what welding and smoothing compare normals' dot with.
    pub fn cos_feature(&self) -> f32 {
        self.feature_angle.to_radians().cos()
    }
}
