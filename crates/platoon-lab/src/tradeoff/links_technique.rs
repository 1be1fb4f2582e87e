//! Vertex links' options as a technique: `links=N` (N directions per element, the other
//! options default) with `+bB` (B bounces), `+nosmooth` (no smoothing), `+vertex` (direct
//! light at each vertex alone, not over its fan) and `+subK` (every mesh subdivided 1:4 K
//! times: the same surfaces with more vertices, the tessellation sweep). The update's time is
//! the technique's too.

use std::fmt;

use anyhow::{bail, Result};
use platoon_core::method::links::{Links, LinksOptions};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LinksTechnique {
    pub directions: u32,
    pub bounces: u32,
    pub smooth: bool,
    pub vertex_light: bool,
    /// Times every mesh is subdivided before (`variant::Variant::Subdivided`).
    pub subdivisions: u32,
}

/// The most subdivisions a technique asks for (each multiplies the triangles by four).
pub const MAX_SUBDIVISIONS: u32 = 5;

impl LinksTechnique {
    pub fn options(self) -> LinksOptions {
        LinksOptions {
            directions: self.directions,
            bounces: self.bounces,
            smooth: self.smooth,
            fan_light: !self.vertex_light,
            ..LinksOptions::default()
        }
    }

    /// The method of a frame this technique renders (solved before its first render).
    pub fn method(self) -> platoon_core::Method {
        platoon_core::Method::Links(Links::new(self.options()))
    }

    pub fn parse(s: &str, value: &str) -> Result<LinksTechnique> {
        let mut parts = value.split('+');
        let directions = match parts.next().map(|v| v.trim().parse::<u32>()) {
            Some(Ok(n)) => n,
            _ => bail!("technique {s:?}: links needs a direction count, e.g. links=256+b2"),
        };
        let mut t = LinksTechnique {
            directions,
            bounces: LinksOptions::default().bounces,
            smooth: true,
            vertex_light: false,
            subdivisions: 0,
        };
        for part in parts {
            let part = part.trim();
            if part == "nosmooth" {
                t.smooth = false;
            } else if part == "vertex" {
                t.vertex_light = true;
            } else if let Some(b) = part.strip_prefix('b').and_then(|b| b.parse().ok()) {
                t.bounces = b;
            } else if let Some(k) = part.strip_prefix("sub").and_then(|k| k.parse().ok()) {
                if k > MAX_SUBDIVISIONS {
                    bail!("technique {s:?}: at most {MAX_SUBDIVISIONS} subdivisions, not {k}");
                }
                t.subdivisions = k;
            } else {
                bail!(
                    "technique {s:?}: unknown links option {part:?} (bB, nosmooth, vertex, subK)"
                );
            }
        }
        t.options()
            .validate()
            .map_err(|e| anyhow::anyhow!("technique {s:?}: {e}"))?;
        Ok(t)
    }
}

impl fmt::Display for LinksTechnique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "links={}", self.directions)?;
        if self.bounces != LinksOptions::default().bounces {
            write!(f, "+b{}", self.bounces)?;
        }
        if !self.smooth {
            write!(f, "+nosmooth")?;
        }
        if self.vertex_light {
            write!(f, "+vertex")?;
        }
        if self.subdivisions > 0 {
            write!(f, "+sub{}", self.subdivisions)?;
        }
        Ok(())
    }
}
