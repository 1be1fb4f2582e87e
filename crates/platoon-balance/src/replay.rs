//! Deterministic replay of recorded per-line cost maps against stated device speeds, so that
//! balancers can be compared free of machine noise. A cost map holds, for every frame of a
//! camera path, the time each line took on the recording device (seconds); a device of speed s
//! renders a line of cost c in c / s, and a part of a line in its share of pixels of that.

use std::path::Path;

use crate::steal::{unstolen_seconds, Stealing};
use crate::steal_history::StealHistory;
use crate::Span;
use crate::{idle_fraction, span_cost, Balancer, FrameMeasure, TracerFrame};
use platoon_scene::error::{Error, Result};

#[derive(Clone, Debug, PartialEq)]
pub struct CostMap {
    /// Pixels per line of the recorded frames: the finest cut a balancer can make.
    pub width: u32,
    /// `frames[f][y]`: cost of line y in frame f.
    pub frames: Vec<Vec<f64>>,
}

/// The comment line that states a map's width.
const WIDTH_KEY: &str = "# width:";

impl CostMap {
    pub fn height(&self) -> usize {
        self.frames.first().map_or(0, |f| f.len())
    }

    /// One frame per line of text, comma-separated line costs; `#` lines are comments, but for
    /// `# width: N` (pixels per line; square frames when absent).
    pub fn parse(text: &str, origin: &Path) -> Result<CostMap> {
        let mut frames = Vec::new();
        let mut width = None;
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if let Some(w) = line.strip_prefix(WIDTH_KEY) {
                let w = w.trim().parse::<u32>().ok().filter(|w| *w > 0);
                width = Some(w.ok_or_else(|| {
                    Error::file(
                        origin,
                        format!("line {}: width must be a positive integer", n + 1),
                    )
                })?);
                continue;
            }
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let costs: std::result::Result<Vec<f64>, _> =
                line.split(',').map(|v| v.trim().parse::<f64>()).collect();
            let costs = costs.map_err(|e| Error::file(origin, format!("line {}: {e}", n + 1)))?;
            if costs.iter().any(|c| !c.is_finite() || *c < 0.0) {
                return Err(Error::file(
                    origin,
                    format!("line {}: costs must be finite and non-negative", n + 1),
                ));
            }
            if frames
                .first()
                .is_some_and(|f: &Vec<f64>| f.len() != costs.len())
            {
                return Err(Error::file(
                    origin,
                    format!("line {}: every frame needs the same number of lines", n + 1),
                ));
            }
            frames.push(costs);
        }
        if frames.is_empty() || frames[0].len() < 3 {
            return Err(Error::file(
                origin,
                "no frames, or frames of fewer than 3 lines",
            ));
        }
        Ok(CostMap {
            width: width.unwrap_or(frames[0].len() as u32),
            frames,
        })
    }

    pub fn load(path: &Path) -> Result<CostMap> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::file(path, format!("cannot read cost map: {e}")))?;
        CostMap::parse(&text, path)
    }

    pub fn to_text(&self, comment: &str) -> String {
        let mut s = format!(
            "# {comment}\n# one frame per line: seconds per pixel line on the recording device\n\
             {WIDTH_KEY} {}\n",
            self.width
        );
        for f in &self.frames {
            let row: Vec<String> = f.iter().map(|c| format!("{c:.6e}")).collect();
            s.push_str(&row.join(","));
            s.push('\n');
        }
        s
    }

    /// The first `frames` frames, cycling if the map is shorter.
    pub fn take(&self, frames: usize) -> CostMap {
        CostMap {
            width: self.width,
            frames: (0..frames)
                .map(|i| self.frames[i % self.frames.len()].clone())
                .collect(),
        }
    }
}

/// Idle fraction of every frame when `balancer` splits the recorded frames between devices of
/// the given relative speeds ([`replay_stealing`] without stealing).
pub fn replay(costs: &CostMap, speeds: &[f64], balancer: &mut dyn Balancer) -> Vec<f64> {
    replay_stealing(costs, speeds, balancer, None, Overhead::default())
        .iter()
        .map(|f| f.idle)
        .collect()
}

/// What a piece of a band costs besides its pixels (seconds): the fixed cost of a dispatch
/// (recording, submitting, waiting, reading back) and of a claim (an atomic between tracers of
/// one process; a message to rank 0 between machines).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overhead {
    pub dispatch: f64,
    pub claim: f64,
}

/// One replayed frame with stealing: the tracers' idle and the time the pieces' overhead
/// took, both as shares of the frame's tracer time (n T_max).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StolenFrame {
    pub idle: f64,
    pub overhead: f64,
    /// Pieces claimed (dispatches besides the heads).
    pub pieces: u32,
    /// The slowest tracer's time (the maps' seconds).
    pub frame_seconds: f64,
}

impl StolenFrame {
    /// Idle with the overhead counted as lost: what the frame lost to balancing.
    pub fn lost(&self) -> f64 {
        self.idle + self.overhead
    }
}

/// The recorded frames split between devices of the given relative speeds: the balancer
/// plans each frame and learns from it. With `stealing` the tails are cut from the costs of
/// the frame before (what a renderer knows), and the tracers claim pieces in the order of
/// their clocks, each piece costing `overhead` besides its pixels and every claim (the last,
/// empty one too) a claim's; the balancer learns what each tracer's planned band would have
/// taken at the speed it rendered at.
pub fn replay_stealing(
    costs: &CostMap,
    speeds: &[f64],
    balancer: &mut dyn Balancer,
    stealing: Option<&Stealing>,
    overhead: Overhead,
) -> Vec<StolenFrame> {
    let (width, height) = (costs.width, costs.height() as u32);
    let n = speeds.len();
    let mut history = StealHistory::default();
    let mut frames = Vec::with_capacity(costs.frames.len());
    let piece = overhead.dispatch + overhead.claim;
    for line_costs in &costs.frames {
        let planned = balancer.plan(width, height, n);
        let board = stealing.and_then(|s| history.board(s, &planned, width, height));
        let head = |i: usize| board.as_ref().map_or(planned[i], |b| b.head(i));
        let time = |i: usize, s: Span| span_cost(line_costs, width, s) / speeds[i];
        let mut clock: Vec<f64> = (0..n).map(|i| time(i, head(i))).collect();
        let mut rendered: Vec<Vec<Span>> = (0..n).map(|i| vec![head(i)]).collect();
        let mut spent = vec![0.0; n];
        let mut pieces = 0;
        if let Some(board) = &board {
            let mut working: Vec<usize> = (0..n).collect();
            while !working.is_empty() {
                // The tracer whose clock is earliest claims next (the lowest on a tie).
                let k = (0..working.len())
                    .min_by(|&a, &b| clock[working[a]].total_cmp(&clock[working[b]]))
                    .expect("a tracer at work");
                let i = working[k];
                clock[i] += overhead.claim;
                spent[i] += overhead.claim;
                match board.claim(i, clock[i]) {
                    Some(piece) => {
                        clock[i] += overhead.dispatch + time(i, piece.span);
                        spent[i] += overhead.dispatch;
                        rendered[i].push(piece.span);
                        pieces += 1;
                    }
                    None => {
                        working.remove(k);
                    }
                }
            }
        }
        let max = clock.iter().copied().fold(0.0, f64::max);
        frames.push(StolenFrame {
            idle: idle_fraction(&clock),
            overhead: if max > 0.0 {
                spent.iter().sum::<f64>() / (n as f64 * max)
            } else {
                0.0
            },
            pieces,
            frame_seconds: max,
        });
        let tracers: Vec<TracerFrame> = (0..n)
            .map(|i| TracerFrame {
                span: planned[i],
                seconds: match board {
                    Some(_) => {
                        unstolen_seconds(line_costs, width, planned[i], &rendered[i], clock[i])
                    }
                    None => clock[i],
                },
            })
            .collect();
        balancer.observe(&FrameMeasure {
            width,
            height,
            tracers: &tracers,
            line_costs,
        });
        let unstolen: Vec<f64> = tracers.iter().map(|t| t.seconds).collect();
        let measured = (pieces > 0).then_some(piece);
        history.learn(line_costs.clone(), max, idle_fraction(&unstolen), measured);
    }
    frames
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::by_name;

    #[test]
    fn parses_what_it_writes_and_rejects_bad_maps() {
        let map = CostMap {
            width: 5,
            frames: vec![vec![1.0, 2.0, 3.0], vec![0.5, 0.25, 0.125]],
        };
        assert_eq!(
            CostMap::parse(&map.to_text("test"), Path::new("x")).unwrap(),
            map
        );
        assert!(CostMap::parse("1,2,3\n1,2\n", Path::new("bad.csv"))
            .unwrap_err()
            .to_string()
            .contains("bad.csv"));
        assert!(CostMap::parse("1,x,3\n", Path::new("bad.csv")).is_err());
        assert!(CostMap::parse("", Path::new("bad.csv")).is_err());
        assert!(CostMap::parse("# width: 0\n1,2,3\n", Path::new("bad.csv")).is_err());
        assert_eq!(CostMap::parse("1,2,3\n", Path::new("x")).unwrap().width, 3);
    }

    #[test]
    fn stealing_takes_up_an_equal_splits_idle_and_pays_for_each_piece() {
        let map = CostMap {
            width: 30,
            frames: vec![vec![1.0; 30]; 4],
        };
        let stealing = Stealing {
            tail: 0.5,
            chunk: 0.01,
            ..Stealing::default()
        };
        let mut none = by_name("none").unwrap();
        // Speeds 1 and 0.5 under an equal split idle 25% (below); with half of each band
        // shared, the fast tracer takes the slow one's tail down to a piece of a chunk.
        let free = replay_stealing(
            &map,
            &[1.0, 0.5],
            none.as_mut(),
            Some(&stealing),
            Overhead::default(),
        );
        for f in &free {
            assert!(f.idle < 0.02 && f.overhead == 0.0 && f.pieces > 4, "{f:?}");
        }
        let costly = Overhead {
            dispatch: 0.05,
            claim: 0.01,
        };
        let paid = replay_stealing(&map, &[1.0, 0.5], none.as_mut(), Some(&stealing), costly);
        for (f, p) in free.iter().zip(&paid) {
            assert!(p.overhead > 0.01 && p.lost() > f.lost(), "{p:?} vs {f:?}");
        }
        // No tail: the plain replay's idle, nothing paid.
        let whole = Stealing {
            tail: 0.0,
            ..stealing
        };
        let plain = replay_stealing(
            &map.take(3),
            &[1.0, 0.5],
            none.as_mut(),
            Some(&whole),
            costly,
        );
        assert!(
            plain.iter().all(|f| (f.idle - 0.25).abs() < 1e-3),
            "{plain:?}"
        );
        // The empty claim at the end of each tracer's work costs a claim.
        assert!(plain.iter().all(|f| f.pieces == 0 && f.overhead > 0.0));
    }

    #[test]
    fn equal_split_of_uniform_costs_on_equal_devices_never_idles() {
        let map = CostMap {
            width: 30,
            frames: vec![vec![1.0; 30]; 5],
        };
        let idle = replay(&map, &[1.0, 1.0, 1.0], by_name("none").unwrap().as_mut());
        assert!(idle.iter().all(|&i| i == 0.0));
        // Unequal devices idle with an equal split: 1.0 vs 0.5 -> (2 - 1) / (2 * 2) = 25%.
        let idle = replay(&map.take(3), &[1.0, 0.5], by_name("none").unwrap().as_mut());
        assert!(idle.iter().all(|&i| (i - 0.25).abs() < 1e-12));
    }
}
