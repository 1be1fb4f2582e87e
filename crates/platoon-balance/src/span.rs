//! The unit a balancer hands out: a run of pixels of the frame.

/// A band of the frame: the pixels [begin, end) in row-major order. It may start and end within
/// a line: with whole lines as the unit, the cut between two devices is off by up to half a
/// line, which at 96 lines and 3 devices alone idles 1.5% (docs/BALANCING.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    pub begin: u32,
    pub end: u32,
}

impl Span {
    pub fn new(begin: u32, end: u32) -> Span {
        Span { begin, end }
    }
    /// Lines [y0, y1) of a frame `width` pixels wide.
    pub fn lines(width: u32, y0: u32, y1: u32) -> Span {
        Span::new(y0 * width, y1 * width)
    }
    pub fn len(&self) -> u32 {
        self.end.saturating_sub(self.begin)
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The first line the span touches.
    pub fn first_line(&self, width: u32) -> u32 {
        self.begin / width.max(1)
    }
    /// One past the last line the span touches.
    pub fn end_line(&self, width: u32) -> u32 {
        if self.is_empty() {
            self.first_line(width)
        } else {
            self.end.div_ceil(width.max(1))
        }
    }
    /// Pixels of line `y` inside the span.
    pub fn pixels_in_line(&self, width: u32, y: u32) -> u32 {
        let (a, b) = (y * width, (y + 1) * width);
        self.end.min(b).saturating_sub(self.begin.max(a))
    }
}
