//! A block's codes sorted into LinuxCNC's modal groups, and the checks LinuxCNC makes before
//! it runs anything (`check_items`, `enhance_block`): two codes of one group, axis words with
//! nothing to use them, a word no code on the line uses.

/// Whether `g` is a canned cycle (G80 is not).
pub(super) fn is_cycle(g: GCode) -> bool {
    matches!(g, 730 | 740 | 810..=890)
}

use super::{err, gname, Interp};
use crate::gcode::{Block, GCode, GcodeError};

/// The G codes understood, by modal group (LinuxCNC's numbering).
const G_GROUPS: &[(u8, &[GCode])] = &[
    (
        0,
        &[
            40, 100, 280, 281, 300, 301, 520, 530, 53, 920, 921, 922, 923,
        ],
    ),
    (
        1,
        &[
            0, 10, 20, 30, 50, 51, 52, 330, 331, 382, 383, 384, 385, 730, 740, 800, 810, 820, 830,
            840, 850, 860, 870, 880, 890,
        ],
    ),
    (2, &[170, 180, 190]),
    (3, &[900, 910]),
    (4, &[901, 911]),
    (5, &[930, 940, 950]),
    (6, &[200, 210]),
    (7, &[400, 410, 411, 420, 421]),
    (8, &[430, 431, 432, 490]),
    (10, &[980, 990]),
    (12, &[540, 550, 560, 570, 580, 590, 591, 592, 593]),
    (13, &[610, 611, 640]),
    (14, &[970]),
];

/// Codes LinuxCNC knows that this interpreter refuses, and why.
const G_REFUSED: &[(GCode, &str)] = &[
    (70, "G7 (lathe diameter mode) is not supported on a mill"),
    (80, "G8 (lathe radius mode) is not supported on a mill"),
    (62, "G6.2 (LinuxCNC's other NURBS form) is not supported"),
    (
        760,
        "G76 (lathe threading cycle) is not supported on a mill",
    ),
    (960, "G96 (constant surface speed) is not supported"),
    (171, "G17.1 (UV plane) is not supported: no U or V axis"),
    (181, "G18.1 (WU plane) is not supported: no U or W axis"),
    (191, "G19.1 (VW plane) is not supported: no V or W axis"),
    (
        700,
        "G70 (lathe finishing cycle) is not supported on a mill",
    ),
    (710, "G71 (lathe roughing cycle) is not supported on a mill"),
    (720, "G72 (lathe roughing cycle) is not supported on a mill"),
];

/// M codes by LinuxCNC's modal group.
fn m_group(m: u32) -> Option<u8> {
    Some(match m {
        0 | 1 | 2 | 30 | 60 => 4,
        62..=68 => 5,
        6 | 61 => 6,
        3..=5 | 19 => 7,
        7..=9 => 8,
        48..=51 => 9,
        100..=199 => 10,
        70..=73 => 11,
        _ => return None,
    })
}

fn m_refused(m: u32) -> String {
    match m {
        52 => "M52 (adaptive feed) is not supported".into(),
        53 => "M53 (feed stop) is not supported".into(),
        98 | 99 => format!("M{m} (Fanuc-style subprogram) is not supported"),
        _ => format!("M{m} is not supported"),
    }
}

fn g_group(g: GCode) -> Option<u8> {
    G_GROUPS
        .iter()
        .find(|(_, codes)| codes.contains(&g))
        .map(|(n, _)| *n)
}

/// A block's codes by group, and the motion it makes.
#[derive(Debug, Clone, Default)]
pub(super) struct Line {
    g: [Option<GCode>; 15],
    m: [Option<u32>; 12],
    /// LinuxCNC's `motion_to_be`: the motion the line makes (its own group 1 code, or the
    /// modal one when it has axis words and no group 0 code takes them).
    pub motion: Option<GCode>,
}

impl Line {
    /// The code of G group `n` on the line.
    pub fn group(&self, n: usize) -> Option<GCode> {
        self.g[n]
    }

    /// The code of M group `n` on the line (group 8, coolant, may hold M7 and M8 together:
    /// read the block's codes for it).
    pub fn m_group(&self, n: usize) -> Option<u32> {
        self.m[n]
    }
}

/// A non-negative integer word (within 0.0001, as LinuxCNC reads them), at least `min`.
pub(super) fn int_word(line: usize, letter: char, v: f64, min: f64) -> Result<u32, GcodeError> {
    let r = v.round();
    if (v - r).abs() > 1e-4 || r < min || r > u32::MAX as f64 {
        return err(
            line,
            format!("{letter}{v}: a whole number of at least {min} is needed"),
        );
    }
    Ok(r as u32)
}

const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// Sorts and checks the block.
pub(super) fn check(it: &Interp, b: &Block) -> Result<Line, GcodeError> {
    let line = b.line;
    let mut l = Line::default();
    for &g in &b.g {
        let Some(n) = g_group(g) else {
            if let Some((_, why)) = G_REFUSED.iter().find(|(c, _)| *c == g) {
                return err(line, *why);
            }
            return err(
                line,
                format!("{} is not a G code of this interpreter", gname(g)),
            );
        };
        if let Some(prev) = l.g[n as usize] {
            // LinuxCNC lets G80 share a line with another motion code, which wins (programs
            // start `G90 G17 G40 G80 G00`).
            if g == 800 {
                continue;
            }
            if prev == 800 {
                l.g[n as usize] = Some(g);
                continue;
            }
            return err(
                line,
                format!(
                    "{} and {} are in the same modal group ({n})",
                    gname(prev),
                    gname(g)
                ),
            );
        }
        l.g[n as usize] = Some(g);
    }
    if b.m.len() > 4 {
        return err(line, "more than four M codes on one line");
    }
    for &m in &b.m {
        let Some(n) = m_group(m) else {
            return err(line, m_refused(m));
        };
        if let Some(prev) = l.m[n as usize] {
            // LinuxCNC takes M7 with M8 on one line.
            if !(n == 8 && prev != m && prev != 9 && m != 9) {
                return err(
                    line,
                    format!("M{prev} and M{m} are in the same modal group ({n})"),
                );
            }
        }
        l.m[n as usize] = Some(m);
    }
    for letter in ['U', 'V', 'W'] {
        if b.word(letter).is_some() {
            return err(line, format!("no {letter} axis on this machine"));
        }
    }
    let polar = b.polar.iter().any(Option::is_some);
    if polar && (b.word('X').is_some() || b.word('Y').is_some()) {
        return err(line, "X or Y words with polar coordinates (@, ^)");
    }
    let axis = polar || AXES.iter().any(|&c| b.word(c).is_some());
    let ijk = ['I', 'J', 'K'].iter().any(|&c| b.word(c).is_some());
    let mode0 = l.g[0];
    let mode1 = l.g[1];
    let covets = matches!(mode0, Some(100 | 280 | 300 | 520 | 920));
    let tlo = l.g[8];
    if let Some(m1) = mode1 {
        if m1 == 800 {
            if axis && !covets {
                return err(
                    line,
                    "axis words with G80 (and no G10, G28, G30, G52 or G92)",
                );
            }
        } else if covets {
            return err(
                line,
                format!(
                    "{} and {} both use the axis words",
                    gname(mode0.unwrap_or(0)),
                    gname(m1)
                ),
            );
        } else if !axis && !matches!(m1, 0 | 10 | 20 | 30 | 52) {
            return err(line, format!("{} without any axis word", gname(m1)));
        }
        // G0/G1 without axis words only set the mode (LinuxCNC would emit a move of
        // length zero).
        if axis || !matches!(m1, 0 | 10) {
            l.motion = Some(m1);
        }
    } else if covets {
        // G10, G28, G30 may go without axis words; G52 and G92 may not.
    } else if axis {
        if it.motion.is_none() && !matches!(tlo, Some(431 | 432)) {
            return err(
                line,
                "axis words with no motion mode (G80 in effect) to use them",
            );
        }
        if tlo != Some(431) {
            l.motion = it.motion;
        }
    } else if ijk && matches!(it.motion, Some(20 | 30)) {
        l.motion = it.motion;
    }
    if matches!(mode0, Some(520 | 920)) && !axis {
        return err(
            line,
            format!("{} without any axis word", gname(mode0.unwrap_or(0))),
        );
    }
    if mode0 == Some(40) {
        if b.word('P').is_none() {
            return err(line, "G4 needs P (the dwell in seconds)");
        }
        if matches!(l.motion, Some(20 | 30)) {
            return err(line, "G4 with G2 or G3: both use P");
        }
    }
    if polar && (mode0.is_some() || !matches!(l.motion, Some(0 | 10))) {
        return err(line, "polar coordinates (@, ^) are for G0 and G1 only");
    }
    if polar {
        // (LinuxCNC's: no angle to take or turn about the origin)
        let cur = it.cur_work();
        let absolute = l.g[3].map_or(it.absolute, |g| g == 900);
        if cur[0] == 0.0 && cur[1] == 0.0 && (!absolute || b.polar[1].is_none()) {
            return err(
                line,
                "polar coordinates at the work origin need ^ (the angle), and G90",
            );
        }
    }
    if mode0 == Some(530) {
        if !matches!(l.motion, Some(0 | 10)) {
            return err(line, "G53 needs G0 or G1 on its line (or in effect)");
        }
        if l.g[3] == Some(910) || (l.g[3].is_none() && !it.absolute) {
            return err(
                line,
                "G53 cannot be used in incremental distance mode (G91)",
            );
        }
    }
    if mode0 == Some(53) && mode1.is_some_and(|m| m != 52) {
        return err(
            line,
            "between G5.2 and G5.3 only further G5.2 codes are allowed",
        );
    }
    check_words(b, &l)?;
    Ok(l)
}

/// LinuxCNC's `check_other_codes`: every word has a code on its line that uses it.
fn check_words(b: &Block, l: &Line) -> Result<(), GcodeError> {
    let line = b.line;
    let motion = l.motion;
    let is = |codes: &[GCode]| motion.is_some_and(|m| codes.contains(&m));
    let cycle = motion.is_some_and(is_cycle);
    let g0 = l.g[0];
    let comp = l.g[7];
    let m5 = l.m[5];
    let m9 = l.m[9];
    let user_m = l.m[10].is_some();
    for c in ['A', 'B', 'C'] {
        if b.word(c).is_some() && cycle {
            return err(line, format!("{c} word with a canned cycle"));
        }
    }
    if b.word('D').is_some() && !matches!(comp, Some(410 | 411 | 420 | 421)) && !is(&[730, 830]) {
        return err(
            line,
            "D word with no G41, G41.1, G42, G42.1, G73 or G83 to use it",
        );
    }
    if b.word('E').is_some() && !matches!(m5, Some(66..=68)) {
        return err(line, "E word with no M66, M67 or M68 to use it");
    }
    if b.word('H').is_some() && !matches!(l.g[8], Some(430 | 432)) {
        return err(line, "H word with no G43 or G43.2 to use it");
    }
    let g10 = g0 == Some(100);
    if b.word('I').is_some() && !is(&[20, 30, 50, 51, 870]) && !g10 {
        return err(
            line,
            "I word with no G2, G3, G5, G5.1, G10 or G87 to use it",
        );
    }
    if b.word('J').is_some() && !is(&[20, 30, 50, 51, 870]) && !g10 {
        return err(
            line,
            "J word with no G2, G3, G5, G5.1, G10 or G87 to use it",
        );
    }
    if b.word('K').is_some() && !is(&[20, 30, 330, 331, 870]) {
        return err(line, "K word with no G2, G3, G33, G33.1 or G87 to use it");
    }
    if b.word('L').is_some()
        && !cycle
        && !is(&[52])
        && !g10
        && !matches!(comp, Some(410 | 411 | 420 | 421))
        && m5 != Some(66)
    {
        return err(
            line,
            "L word with no G10, cutter compensation, canned cycle, M66 or G5.2 to use it",
        );
    }
    if let Some(p) = b.word('P') {
        let ok = matches!(g0, Some(100 | 40))
            || l.g[13] == Some(640)
            || is(&[820, 860, 880, 890, 50, 52, 20, 30, 740, 840])
            || matches!(m9, Some(50 | 51))
            || matches!(m5, Some(62..=66))
            || l.m[7] == Some(19)
            || user_m;
        if !ok {
            return err(
                line,
                "P word with no G2, G3, G4, G5, G5.2, G10, G64, G74, G82, G84, G86, G88, G89, \
                 M19, M50, M51, M62-M66 or M100-M199 to use it",
            );
        }
        if is(&[20, 30]) {
            let r = p.round();
            if (p - r).abs() > 0.001 || r < 1.0 {
                return err(
                    line,
                    format!("P{p} with G2/G3: a whole number of turns, 1 or more"),
                );
            }
        }
    }
    if b.word('Q').is_some() {
        let ok = is(&[830, 730, 50])
            || user_m
            || matches!(m5, Some(66..=68))
            || g10
            || l.m[6] == Some(61)
            || l.m[7] == Some(19)
            || l.g[13] == Some(640);
        if !ok {
            return err(
                line,
                "Q word with no G5, G10, G64, G73, G83, M19, M61, M66, M67, M68 or M100-M199 to \
                 use it",
            );
        }
    }
    if b.word('R').is_some() && !is(&[20, 30, 730]) && !cycle && !g10 && l.m[7] != Some(19) {
        return err(
            line,
            "R word with no G2, G3, G10, M19 or canned cycle to use it",
        );
    }
    if is(&[330, 331]) {
        if b.word('K').is_none() {
            return err(line, "G33 and G33.1 need K (the pitch)");
        }
        if b.word('F').is_some() {
            return err(
                line,
                "F word with G33 or G33.1 (the spindle sets the speed)",
            );
        }
    }
    Ok(())
}
