//! Layered hit buffers' options as a technique: `lhb=SET` (a direction set: ico320, oct32,
//! halton144...) with `+rR` (R texels a side), `+cC` (cone radius C texels), `+bB` (B lookup
//! bounces), `+lL` (L layers a texel), `+exact` (the rasterizer without a capacity) and
//! `+rebuild` (every buffer rebuilt each frame); the other options default. The buffers' build is in every render's device time.

use std::fmt;

use anyhow::{bail, Result};
use platoon_core::method::lhb::directions::DirectionSet;
use platoon_core::method::lhb::{Lhb, LhbOptions, RasterVariant};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LhbTechnique(pub LhbOptions);

impl Eq for LhbTechnique {}

impl std::hash::Hash for LhbTechnique {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.to_string().hash(h);
    }
}

impl LhbTechnique {
    /// The method of a frame this technique renders (prepared before its first render).
    pub fn method(self) -> platoon_core::Method {
        platoon_core::Method::Lhb(Lhb::new(self.0))
    }

    pub fn parse(s: &str, value: &str) -> Result<LhbTechnique> {
        let mut parts = value.split('+');
        let mut o = LhbOptions::default();
        match parts.next().map(str::trim) {
            Some(set) if !set.is_empty() => {
                o.directions =
                    DirectionSet::parse(set).map_err(|e| anyhow::anyhow!("technique {s:?}: {e}"))?
            }
            _ => bail!("technique {s:?}: lhb needs a direction set, e.g. lhb=ico320+r128"),
        }
        for part in parts {
            let part = part.trim();
            let number = |prefix: &str| part.strip_prefix(prefix).and_then(|v| v.parse().ok());
            if part == "exact" {
                o.variant = RasterVariant::Exact;
            } else if part == "rebuild" {
                o.rebuild = true;
            } else if let Some(r) = number("r") {
                o.resolution = r;
            } else if let Some(b) = number("b") {
                o.bounces = b;
            } else if let Some(l) = number("l") {
                o.layers = l;
            } else if let Some(c) = part.strip_prefix('c').and_then(|v| v.parse().ok()) {
                o.cone = c;
            } else {
                bail!(
                    "technique {s:?}: unknown lhb option {part:?} (rR, cC, bB, lL, exact, rebuild)"
                );
            }
        }
        o.validate()
            .map_err(|e| anyhow::anyhow!("technique {s:?}: {e}"))?;
        Ok(LhbTechnique(o))
    }
}

impl fmt::Display for LhbTechnique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (o, d) = (&self.0, LhbOptions::default());
        write!(f, "lhb={}", o.directions)?;
        if o.resolution != d.resolution {
            write!(f, "+r{}", o.resolution)?;
        }
        if o.cone != d.cone {
            write!(f, "+c{}", o.cone)?;
        }
        if o.bounces != d.bounces {
            write!(f, "+b{}", o.bounces)?;
        }
        if o.layers != d.layers {
            write!(f, "+l{}", o.layers)?;
        }
        if o.variant == RasterVariant::Exact {
            write!(f, "+exact")?;
        }
        if o.rebuild {
            write!(f, "+rebuild")?;
        }
        Ok(())
    }
}
