//! STUB (not committed): the API of the helper's module, to compile the firmware against.
#![allow(missing_docs, unused)]
pub const MAX_AXES: usize = 8;
#[derive(Debug, Clone, Copy)]
pub struct PathLimits {
    pub naxes: usize,
    pub ts: f64,
    pub vmax: [f64; 8],
    pub amax: [f64; 8],
    pub jmax: [f64; 8],
    pub accel: f64,
    pub jerk: f64,
}
#[derive(Debug, Clone, Copy)]
pub enum Geom {
    Line {
        end: [f64; 8],
    },
    Arc {
        u: usize,
        v: usize,
        centre: [f64; 2],
        ccw: bool,
        end: [f64; 8],
    },
    Dwell {
        time: f64,
    },
}
#[derive(Debug, Clone, Copy)]
pub enum Transition {
    Exact,
    MaxDeviation(f64),
    CornerDistance(f64),
}
#[derive(Debug, Clone, Copy)]
pub enum BlendSpeed {
    Low,
    Previous,
    Next,
    High,
}
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    pub id: u32,
    pub geom: Geom,
    pub feed: f64,
    pub transition: Transition,
    pub blend: BlendSpeed,
    pub last: bool,
}
#[derive(Debug, Clone, Copy)]
pub enum OutputAt {
    Start,
    End,
    Distance(f64),
}
#[derive(Debug, Clone, Copy)]
pub struct OutputAction {
    pub bit: u8,
    pub on: bool,
    pub at: OutputAt,
}
#[derive(Debug, Clone, Copy)]
pub enum PathEvent {
    SegmentStart { id: u32 },
    SegmentEnd { id: u32 },
    Output { bit: u8, on: bool, id: u32 },
    Starving,
    Idle,
}
#[derive(Debug, Clone, Copy)]
pub enum PathError {
    NotFinite,
    Full,
    ZeroLength,
    Other,
}
#[derive(Debug, Clone)]
pub struct Path;
impl Path {
    pub fn with_capacity(segments: usize) -> Self {
        todo!()
    }
    pub fn reset(
        &mut self,
        start: [f64; 8],
        lim: PathLimits,
        lookahead: usize,
    ) -> Result<(), PathError> {
        todo!()
    }
    pub fn push(&mut self, seg: Segment) -> Result<(), PathError> {
        todo!()
    }
    pub fn push_output(&mut self, o: OutputAction) -> Result<(), PathError> {
        todo!()
    }
    pub fn tick(&mut self, feed_override: f64, ev: &mut impl FnMut(PathEvent)) -> [f64; 8] {
        todo!()
    }
    pub fn halt(&mut self, decel: f64, jerk: f64) {
        todo!()
    }
    pub fn clear(&mut self, aborted: &mut impl FnMut(u32)) {
        todo!()
    }
    pub fn free(&self) -> usize {
        todo!()
    }
    pub fn queued(&self) -> usize {
        todo!()
    }
    pub fn is_moving(&self) -> bool {
        todo!()
    }
    pub fn speed(&self) -> f64 {
        todo!()
    }
    pub fn accel(&self) -> f64 {
        todo!()
    }
    pub fn position(&self) -> [f64; 8] {
        todo!()
    }
    pub fn current_id(&self) -> Option<u32> {
        todo!()
    }
    pub fn distance(&self) -> f64 {
        todo!()
    }
}
