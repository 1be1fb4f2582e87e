//! A border render (Mitsuba's film crop, Cycles' render region with "crop to region"): the
//! frame renders a window of the image its camera frames, and its film is that window's size.
//! Camera rays and random numbers are those of the whole image's pixels (the kernels add the
//! window's offset, `shaders/common/scene.glsl`), so a path-traced window holds the same bits
//! as the same pixels of the whole render.

use std::fmt;

/// The window of an image to render, in its pixels (`--crop X,Y,W,H`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Region {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// Where a frame's pixels lie in the image its camera frames: the frame's first pixel and the
/// whole image's size (`FrameParams::crop`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Crop {
    pub x: u32,
    pub y: u32,
    pub image_width: u32,
    pub image_height: u32,
}

impl Region {
    /// `X,Y,W,H`: the window's top-left pixel and its size.
    pub fn parse(s: &str) -> Result<Region, String> {
        let numbers: Vec<&str> = s.split(',').map(str::trim).collect();
        let [x, y, width, height] = numbers[..] else {
            return Err(format!(
                "{s:?} is not X,Y,W,H (the window's top-left pixel, its width and height)"
            ));
        };
        let number = |what: &str, v: &str| {
            v.parse::<u32>()
                .map_err(|_| format!("{what} {v:?} is not a whole number of pixels"))
        };
        Ok(Region {
            x: number("X", x)?,
            y: number("Y", y)?,
            width: number("W", width)?,
            height: number("H", height)?,
        })
    }

    /// Whether the window is a non-empty part of a `width` x `height` image.
    pub fn check(&self, width: u32, height: u32) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!("the window {self} is empty"));
        }
        let right = self.x as u64 + self.width as u64;
        let bottom = self.y as u64 + self.height as u64;
        if right > width as u64 || bottom > height as u64 {
            return Err(format!(
                "the window {self} reaches past the {width} x {height} image \
                 (to column {right}, line {bottom})"
            ));
        }
        Ok(())
    }

    /// The frame's placement in a `width` x `height` image.
    pub fn crop_of(&self, width: u32, height: u32) -> Crop {
        Crop {
            x: self.x,
            y: self.y,
            image_width: width,
            image_height: height,
        }
    }
}

impl fmt::Display for Region {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x, self.y, self.width, self.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_parse_and_must_lie_in_the_image() {
        let r = Region::parse("8, 4,16,12").unwrap();
        assert_eq!((r.x, r.y, r.width, r.height), (8, 4, 16, 12));
        assert!(r.check(24, 16).is_ok());
        assert!(r.check(23, 16).unwrap_err().contains("column 24"));
        assert!(r.check(24, 15).unwrap_err().contains("line 16"));
        assert!(Region::parse("0,0,0,4")
            .unwrap()
            .check(8, 8)
            .unwrap_err()
            .contains("empty"));
        assert!(Region::parse("1,2,3").unwrap_err().contains("X,Y,W,H"));
        assert!(Region::parse("1,2,3,-4").unwrap_err().contains("\"-4\""));
    }
}
