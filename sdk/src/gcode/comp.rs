//! Cutter radius compensation (G41/G42) in the plane: the programmed path's lines and arcs
//! offset by the tool radius, arcs added at convex corners. SKELETON: the API is fixed, the
//! bodies are to be written.

/// Which side of the programmed path the tool runs on, looking along the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// G41.
    Left,
    /// G42.
    Right,
}

/// A programmed move in the plane's coordinates (first, second axis of the plane); it starts
/// where the one before ended.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub enum Piece {
    Line {
        end: [f64; 2],
    },
    Arc {
        end: [f64; 2],
        centre: [f64; 2],
        ccw: bool,
    },
}

/// A move of the tool's centre.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub enum Offset {
    Line {
        start: [f64; 2],
        end: [f64; 2],
    },
    Arc {
        start: [f64; 2],
        end: [f64; 2],
        centre: [f64; 2],
        ccw: bool,
    },
}

/// What the tool cannot do: gouge, a first move shorter than the radius, an arc smaller than
/// the tool on its inside.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompError(pub String);

/// A compensated path, one programmed move behind (a corner is known only when the next move
/// is). `T` travels with each programmed move (the caller's line number, feed, the other axes'
/// end) and comes out with every piece made from it.
#[derive(Debug, Clone)]
pub struct Compensator<T> {
    _data: Option<T>,
}

impl<T: Clone> Compensator<T> {
    /// Compensation starts with the tool's centre at `start`, on `side`, with `radius` (> 0).
    pub fn new(_start: [f64; 2], _side: Side, _radius: f64) -> Self {
        todo!()
    }

    /// The next programmed move and its payload. The first is the entry move. What is now
    /// known of the moves before it is appended to `out`: each piece with its `corner` flag
    /// (`true` for an arc added at a convex corner, which carries the payload of the move
    /// after the corner) and its payload.
    pub fn push(
        &mut self,
        _piece: Piece,
        _data: T,
        _out: &mut Vec<(Offset, bool, T)>,
    ) -> Result<(), CompError> {
        todo!()
    }

    /// Ends compensation (G40): the last move's pieces appended to `out`. Returns where the
    /// tool's centre is; the next move (the exit move) starts there.
    pub fn finish(&mut self, _out: &mut Vec<(Offset, bool, T)>) -> Result<[f64; 2], CompError> {
        todo!()
    }
}
