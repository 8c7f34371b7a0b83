//! Coordinate systems and offsets: G10, G28/G30 (and .1), G43/G49, G52, G53's target,
//! G54–G59.3, G92 and its variants.

use super::{err, gname, Interp};
use crate::gcode::{Block, GCode, GcodeError, Op, OpKind, Params, Pos};

/// Axis letters in [`Pos`] order.
pub(super) const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// Work → machine: `machine = R(work + g92) + origin + tool`, R the rotation about Z.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    pub origin: Pos,
    /// Degrees, counter-clockwise about Z.
    pub rotation: f64,
    pub g92: Pos,
    pub tool: Pos,
}

/// `v` rotated by `deg` about Z (X and Y only).
pub(super) fn rotate(mut v: Pos, deg: f64) -> Pos {
    if deg != 0.0 {
        let (s, c) = deg.to_radians().sin_cos();
        let (x, y) = (v[0], v[1]);
        v[0] = x * c - y * s;
        v[1] = x * s + y * c;
    }
    v
}

fn add(a: Pos, b: Pos) -> Pos {
    std::array::from_fn(|i| a[i] + b[i])
}

fn sub(a: Pos, b: Pos) -> Pos {
    std::array::from_fn(|i| a[i] - b[i])
}

impl Frame {
    pub fn to_machine(self, w: Pos) -> Pos {
        add(
            add(rotate(add(w, self.g92), self.rotation), self.origin),
            self.tool,
        )
    }

    pub fn to_work(self, m: Pos) -> Pos {
        sub(
            rotate(sub(sub(m, self.origin), self.tool), -self.rotation),
            self.g92,
        )
    }
}

/// The first parameter (X) of coordinate system `n` (1..=9); its R is 9 further on.
fn cs_base(n: u32) -> u32 {
    5201 + 20 * n
}

impl Interp {
    /// Axis words of the block, converted to mm (X Y Z) and degrees (A B C).
    pub(super) fn axis_words(&self, b: &Block) -> [Option<f64>; 6] {
        std::array::from_fn(|i| {
            b.word(AXES[i])
                .map(|v| if i < 3 { v * self.k() } else { v })
        })
    }

    /// The end of a move in work coordinates: the axis words, absolute or incremental.
    /// Polar coordinates (`@` distance, `^` angle in degrees) give X and Y about the work
    /// origin, as LinuxCNC's: absolute, the point at that distance and angle (the one missing
    /// taken from the current point); incremental, the current point's distance and angle
    /// increased by them.
    pub(super) fn target(&self, b: &Block) -> Pos {
        let cur = self.cur_work();
        let w = self.axis_words(b);
        let mut t: Pos = std::array::from_fn(|i| match w[i] {
            Some(v) if self.absolute => v,
            Some(v) => cur[i] + v,
            None => cur[i],
        });
        let [r, a] = b.polar;
        if r.is_some() || a.is_some() {
            let (r0, a0) = (cur[0].hypot(cur[1]), cur[1].atan2(cur[0]));
            let r = r.map(|v| v * self.k());
            let a = a.map(f64::to_radians);
            let (r, a) = if self.absolute {
                (r.unwrap_or(r0), a.unwrap_or(a0))
            } else {
                (r0 + r.unwrap_or(0.0), a0 + a.unwrap_or(0.0))
            };
            t[0] = r * a.cos();
            t[1] = r * a.sin();
        }
        t
    }

    /// The active system's offsets from #5221… (#5220 says which).
    pub(super) fn load_coordinate_system(&mut self, params: &Params) {
        let base = cs_base(self.cs);
        for i in 0..6 {
            self.origin[i] = params.get(base + i as u32).unwrap_or(0.0);
        }
        self.rotation = params.get(base + 9).unwrap_or(0.0);
    }

    /// The G92 offsets from #5211…, when #5210 says they are on.
    pub(super) fn load_g92(&mut self, params: &Params) {
        let on = params.get(5210).unwrap_or(0.0) != 0.0;
        for i in 0..6 {
            self.g92[i] = if on {
                params.get(5211 + i as u32).unwrap_or(0.0)
            } else {
                0.0
            };
        }
    }

    /// An error when cutter radius compensation is on (even with a zero radius).
    pub(super) fn no_comp(&self, line: usize, what: &str) -> Result<(), GcodeError> {
        if self.comp_mode != super::CompMode::Off {
            return err(
                line,
                format!("cannot {what} with cutter radius compensation on"),
            );
        }
        Ok(())
    }

    /// G54–G59.3.
    pub(super) fn select_coordinate_system(
        &mut self,
        line: usize,
        g: GCode,
        params: &mut Params,
    ) -> Result<(), GcodeError> {
        let n = u32::from(match g {
            540..=590 => (g - 540) / 10 + 1,
            _ => g - 591 + 7,
        });
        if n != self.cs {
            self.no_comp(line, "change the coordinate system")?;
        }
        self.cs = n;
        params.set(5220, n as f64);
        self.load_coordinate_system(params);
        Ok(())
    }

    /// G10 L1, L2, L10, L20.
    pub(super) fn g10(&mut self, b: &Block, params: &mut Params) -> Result<(), GcodeError> {
        let line = b.line;
        let Some(l) = b.word('L') else {
            return err(line, "G10 needs L (L1, L2, L10 or L20)");
        };
        let l = super::modal::int_word(line, 'L', l, 0.0)?;
        let Some(p) = b.word('P') else {
            return err(line, format!("G10 L{l} needs P"));
        };
        let p = super::modal::int_word(line, 'P', p, 0.0)?;
        let words = self.axis_words(b);
        match l {
            2 | 20 => {
                if p > 9 {
                    return err(line, format!("G10 L{l} P{p}: P is 0 to 9"));
                }
                for c in ['I', 'J', 'K', 'Q'] {
                    if b.word(c).is_some() {
                        return err(line, format!("{c} word with G10 L{l}"));
                    }
                }
                let n = if p == 0 { self.cs } else { p };
                if n == self.cs {
                    self.no_comp(line, "change the active coordinate system")?;
                }
                let base = cs_base(n);
                let rotation = match b.word('R') {
                    Some(_) if l == 20 => return err(line, "R word with G10 L20"),
                    Some(r) => r,
                    None => params.get(base + 9).unwrap_or(0.0),
                };
                let mut origin: Pos =
                    std::array::from_fn(|i| params.get(base + i as u32).unwrap_or(0.0));
                if l == 2 {
                    for i in 0..6 {
                        if let Some(v) = words[i] {
                            origin[i] = v;
                        }
                    }
                } else {
                    // L20: the origin that makes the current position read the values.
                    let target = super::Frame {
                        origin,
                        rotation,
                        g92: self.g92,
                        tool: self.tool_offset,
                    };
                    let mut w = target.to_work(self.position);
                    for i in 0..6 {
                        if let Some(v) = words[i] {
                            w[i] = v;
                        }
                    }
                    let full = sub(
                        sub(self.position, self.tool_offset),
                        rotate(add(w, self.g92), rotation),
                    );
                    let xy = words[0].is_some() || words[1].is_some();
                    for i in 0..6 {
                        if words[i].is_some() || (i < 2 && xy && rotation != 0.0) {
                            origin[i] = full[i];
                        }
                    }
                }
                for (i, v) in origin.iter().enumerate() {
                    params.set(base + i as u32, *v);
                }
                params.set(base + 9, rotation);
                if n == self.cs {
                    self.load_coordinate_system(params);
                }
                Ok(())
            }
            1 | 10 => {
                for c in ['I', 'J', 'Q'] {
                    if b.word(c).is_some() {
                        return err(
                            line,
                            format!("{c} word with G10 L{l}: lathe tool data are not supported"),
                        );
                    }
                }
                if p < 1 {
                    return err(
                        line,
                        format!("G10 L{l} P{p}: P is a tool number, 1 or more"),
                    );
                }
                let k = self.k();
                let frame = self.frame();
                let Some(tool) = self.tools.tools.iter_mut().find(|t| t.number == p) else {
                    return err(line, format!("G10 L{l}: tool {p} is not in the tool table"));
                };
                if l == 1 {
                    for (o, w) in tool.offset.iter_mut().zip(words) {
                        if let Some(v) = w {
                            *o = v;
                        }
                    }
                } else {
                    // L10: the offset that, applied with G43, makes the current position
                    // read the values.
                    let mut w = frame.to_work(self.position);
                    for i in 0..6 {
                        if let Some(v) = words[i] {
                            w[i] = v;
                        }
                    }
                    let full = sub(
                        sub(self.position, frame.origin),
                        rotate(add(w, frame.g92), frame.rotation),
                    );
                    let xy = words[0].is_some() || words[1].is_some();
                    for i in 0..6 {
                        if words[i].is_some() || (i < 2 && xy && frame.rotation != 0.0) {
                            tool.offset[i] = full[i];
                        }
                    }
                }
                if let Some(r) = b.word('R') {
                    tool.diameter = 2.0 * r * k;
                }
                self.publish_tool(params);
                Ok(())
            }
            _ => err(
                line,
                format!("G10 L{l} is not supported (L1, L2, L10, L20 are)"),
            ),
        }
    }

    /// G28.1 / G30.1: the machine position into #5161… / #5181….
    pub(super) fn store_home(&mut self, g: GCode, params: &mut Params) {
        let base = if g == 281 { 5161 } else { 5181 };
        for (i, v) in self.position.iter().enumerate() {
            params.set(base + i as u32, *v);
        }
    }

    /// G28 / G30: through the axis words' point (if any) to the stored position, only the
    /// named axes (all when none is named), at rapid.
    pub(super) fn go_home(
        &mut self,
        b: &Block,
        g: GCode,
        params: &mut Params,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let line = b.line;
        self.no_comp(line, &format!("use {}", gname(g)))?;
        let words = self.axis_words(b);
        let any = words.iter().any(Option::is_some);
        if any {
            let end = self.frame().to_machine(self.target(b));
            self.rapid(line, end, out);
        }
        let base = if g == 280 { 5161 } else { 5181 };
        let mut end = self.position;
        for i in 0..6 {
            if !any || words[i].is_some() {
                end[i] = params.get(base + i as u32).unwrap_or(0.0);
            }
        }
        self.rapid(line, end, out);
        Ok(())
    }

    /// A rapid from here to `end` (machine).
    pub(super) fn rapid(&mut self, line: usize, end: Pos, out: &mut Vec<Op>) {
        out.push(Op {
            line,
            kind: OpKind::Rapid {
                start: self.position,
                end,
                blend: self.blend,
            },
        });
        self.position = end;
    }

    /// G52, G92, G92.1, G92.2, G92.3.
    pub(super) fn axis_offsets(
        &mut self,
        b: &Block,
        g: GCode,
        params: &mut Params,
    ) -> Result<(), GcodeError> {
        self.no_comp(b.line, &format!("use {}", gname(g)))?;
        let words = self.axis_words(b);
        match g {
            520 | 920 => {
                let mut off = self.g92;
                if g == 520 {
                    for i in 0..6 {
                        if let Some(v) = words[i] {
                            off[i] = v;
                        }
                    }
                } else {
                    // The offset that makes the current position read the values.
                    let f = self.frame();
                    let q = rotate(sub(sub(self.position, f.origin), f.tool), -f.rotation);
                    for i in 0..6 {
                        if let Some(v) = words[i] {
                            off[i] = q[i] - v;
                        }
                    }
                }
                self.g92 = off;
                for (i, v) in off.iter().enumerate() {
                    params.set(5211 + i as u32, *v);
                }
                params.set(5210, 1.0);
            }
            921 => {
                self.g92 = [0.0; 6];
                for n in 5210..=5219 {
                    params.set(n, 0.0);
                }
            }
            922 => {
                self.g92 = [0.0; 6];
                params.set(5210, 0.0);
            }
            _ => {
                params.set(5210, 1.0);
                self.load_g92(params);
            }
        }
        Ok(())
    }

    /// G43, G43.1, G43.2, G49.
    pub(super) fn set_tool_length(&mut self, b: &Block, g: GCode) -> Result<(), GcodeError> {
        let line = b.line;
        let words = self.axis_words(b);
        let table = |it: &Interp, h: u32| -> Result<Pos, GcodeError> {
            if h == 0 {
                return Ok([0.0; 6]);
            }
            match it.tools.tools.iter().find(|t| t.number == h) {
                Some(t) => Ok(t.offset),
                None => err(line, format!("tool H{h} is not in the tool table")),
            }
        };
        let h = match b.word('H') {
            Some(h) => Some(super::modal::int_word(line, 'H', h, 0.0)?),
            None => None,
        };
        let off = match g {
            490 => [0.0; 6],
            430 => table(self, h.unwrap_or(self.tool))?,
            431 => {
                let mut o = self.tool_offset;
                for i in 0..6 {
                    if let Some(v) = words[i] {
                        o[i] = v;
                    }
                }
                o
            }
            _ => {
                let any = words.iter().any(Option::is_some);
                let add_on = match (h, any) {
                    (Some(_), true) => return err(line, "G43.2 takes H or axis words, not both"),
                    (None, false) => return err(line, "G43.2 needs H or axis words"),
                    (Some(h), false) => table(self, h)?,
                    (None, true) => std::array::from_fn(|i| words[i].unwrap_or(0.0)),
                };
                add(self.tool_offset, add_on)
            }
        };
        // The programmed point stays where it is on the machine while compensation runs
        // (elsewhere the machine position is the truth already).
        let old = self.frame();
        self.tool_offset = off;
        self.tlo_code = g;
        let new = self.frame();
        if let Some(run) = self.comp.as_mut() {
            run.prog = new.to_work(old.to_machine(run.prog));
        }
        Ok(())
    }
}
