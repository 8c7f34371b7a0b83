//! `mcctl group home|status|arc`: axes groups (layout 1.11) over the SDK's [`Group::home`]
//! and [`Group::settings`], and (layout 1.13) a move-queue arc in a plane given by a normal
//! vector ([`Group::move_circular_normal`]). A group's axes are its group axis indices (0: its
//! X, its first axis), not card axes.
//!
//! [`Group::home`]: crate::Group::home
//! [`Group::settings`]: crate::Group::settings
//! [`Group::move_circular_normal`]: crate::Group::move_circular_normal

use super::args::positive;
use super::on_card;
use crate::{Card, GroupState, MoveOptions, NormalArc, PathLimits, Result};
use clap::Subcommand;
use serde_json::json;
use std::process::ExitCode;
use std::time::Duration;

/// How long `mcctl group home` waits for every stage to be homed.
const HOME_WAIT: Duration = Duration::from_secs(120);

/// `mcctl group`'s actions.
#[derive(Subcommand)]
pub enum Action {
    /// MC_GroupHome: home GROUP's axes in stages, a stage once the one before it is homed and
    /// at rest, each axis with its own homing settings; waited for. Without --order, the
    /// group's configured home order. Prints the stages run and each member's position.
    Home {
        group: usize,
        /// Stages of group axis indices (0: the group's X), stages separated by `;`, a
        /// stage's axes by `,`: "2;0,1" homes Z, then X and Y together.
        #[arg(long, value_parser = parse_order)]
        order: Option<Order>,
        #[arg(long)]
        json: bool,
    },
    /// GROUP's state, its card axes and its configured home order.
    Status {
        group: usize,
        #[arg(long)]
        json: bool,
    },
    /// MC_MoveCircular in a plane given by a normal vector (layout 1.13): counter-clockwise
    /// about --normal in the plane of group axes --axes through where the group stands, around
    /// --centre to --end (on those axes, their user units; an end at the start: a full turn),
    /// --turns more full turns; --helix gives the other group axes' targets (a helix). A
    /// rest-to-rest S-curve along the path within --feed, --accel, --jerk; waited for. Prints
    /// where the group's axes ended.
    Arc {
        group: usize,
        /// The plane's three group axes: "a,b,c".
        #[arg(long, value_parser = parse_axes)]
        axes: Triple<usize>,
        /// The normal on them: "x,y,z" (any length but 0).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_point)]
        normal: Triple<f64>,
        /// The centre on the three axes: "x,y,z".
        #[arg(long, allow_hyphen_values = true, value_parser = parse_point)]
        centre: Triple<f64>,
        /// The end on the three axes: "x,y,z".
        #[arg(long, allow_hyphen_values = true, value_parser = parse_point)]
        end: Triple<f64>,
        /// The end may lie off the plane along the normal (a helix along it).
        #[arg(long)]
        rise: bool,
        /// Full turns added to the arc.
        #[arg(long, default_value_t = 0)]
        turns: u32,
        /// The other group axes' targets, in group order: "x,y" (default: they stay).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list)]
        helix: Option<List>,
        /// The centre, the end and the targets from where the group stands.
        #[arg(long)]
        relative: bool,
        /// Feed along the path (the first group axis's units per second).
        #[arg(long, allow_negative_numbers = true, value_parser = positive("--feed"))]
        feed: f64,
        /// Acceleration (and deceleration) along the path.
        #[arg(long, allow_negative_numbers = true, value_parser = positive("--accel"))]
        accel: f64,
        /// Jerk along the path.
        #[arg(long, allow_negative_numbers = true, value_parser = positive("--jerk"))]
        jerk: f64,
        #[arg(long)]
        json: bool,
    },
}

/// Three values from the command line ("a,b,c").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triple<T>(pub [T; 3]);

/// Values from the command line ("x,y,...").
#[derive(Clone, Debug, PartialEq)]
pub struct List(pub Vec<f64>);

/// `"x,y,..."` → the finite numbers.
pub fn parse_list(s: &str) -> std::result::Result<List, String> {
    s.split(',')
        .map(|x| {
            let x = x.trim();
            x.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("`{x}` is not a finite number (values: \"x,y,...\")"))
        })
        .collect::<std::result::Result<_, _>>()
        .map(List)
}

/// `"x,y,z"` → three finite numbers.
pub fn parse_point(s: &str) -> std::result::Result<Triple<f64>, String> {
    let v = parse_list(s)?.0;
    <[f64; 3]>::try_from(v)
        .map(Triple)
        .map_err(|v| format!("three values \"x,y,z\" needed, got {}", v.len()))
}

/// `"a,b,c"` → three group axis indices.
pub fn parse_axes(s: &str) -> std::result::Result<Triple<usize>, String> {
    let v = s
        .split(',')
        .map(|i| {
            let i = i.trim();
            i.parse::<usize>()
                .map_err(|_| format!("`{i}` is not a group axis index (axes: \"a,b,c\")"))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    <[usize; 3]>::try_from(v)
        .map(Triple)
        .map_err(|v| format!("three group axes \"a,b,c\" needed, got {}", v.len()))
}

/// A home order from the command line: stages of group axis indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Order(pub Vec<Vec<usize>>);

/// `"2;0,1"` → `[[2], [0, 1]]`. An empty stage (`"2;"`) is kept, for the card to refuse
/// (`HomeStage`) as it refuses one from any caller.
pub fn parse_order(s: &str) -> std::result::Result<Order, String> {
    s.split(';')
        .map(|stage| {
            let stage = stage.trim();
            if stage.is_empty() {
                return Ok(Vec::new());
            }
            stage
                .split(',')
                .map(|i| {
                    i.trim().parse::<usize>().map_err(|_| {
                        format!(
                            "`{}` is not a group axis index: an order is stages of indices, \
                             `;` between stages, `,` within one (\"2;0,1\")",
                            i.trim()
                        )
                    })
                })
                .collect()
        })
        .collect::<std::result::Result<_, _>>()
        .map(Order)
}

/// Run one action on the card.
pub fn run(uri: &str, action: Action) -> ExitCode {
    on_card(uri, |c| match action {
        Action::Home { group, order, json } => {
            home(c, group, order.map(|o| o.0).unwrap_or_default(), json)
        }
        Action::Status { group, json } => status(c, group, json),
        Action::Arc {
            group,
            axes,
            normal,
            centre,
            end,
            rise,
            turns,
            helix,
            relative,
            feed,
            accel,
            jerk,
            json,
        } => {
            let arc = NormalArc {
                axes: axes.0,
                normal: normal.0,
                centre: centre.0,
                end: end.0,
                rise,
                turns,
            };
            let helix = helix.map(|h| h.0).unwrap_or_default();
            let opts = MoveOptions {
                relative,
                ..MoveOptions::default()
            };
            let lim = PathLimits::new(feed, accel, jerk);
            arc_move(c, group, &arc, &helix, &lim, opts, json)
        }
    })
}

/// How long `mcctl group arc` waits for its move.
const MOVE_WAIT: Duration = Duration::from_secs(600);

/// `mcctl group arc`: the move queued and waited for; where the group's axes ended.
pub fn arc_move(
    card: &Card,
    group: usize,
    arc: &NormalArc,
    helix: &[f64],
    lim: &PathLimits,
    opts: MoveOptions,
    json: bool,
) -> Result<String> {
    let g = card.group(group)?;
    let m = g.move_circular_normal(arc, helix, lim, opts)?;
    match card.sim() {
        // A stepped card: step it until the move ends.
        Some(sim) => {
            let rate = u64::from(card.info().servo_rate_hz);
            let mut waited = 0;
            loop {
                match m.wait(Duration::ZERO) {
                    Err(crate::Error::Timeout(_)) if waited < MOVE_WAIT.as_secs() * rate => {
                        sim.step(rate / 100);
                        waited += rate / 100;
                        super::interrupt::check()?;
                    }
                    r => break r?,
                }
            }
        }
        None => m.wait(MOVE_WAIT)?,
    }
    let axes = g.settings()?.map(|s| s.axes).unwrap_or_default();
    let st = card.statuses(&axes)?;
    let at: Vec<f64> = st.iter().map(|s| s.command_position).collect();
    Ok(if json {
        json!({ "group": group, "axes": axes, "position": at }).to_string()
    } else {
        let mut out = format!("group {group}: arc done\n");
        for (a, p) in axes.iter().zip(&at) {
            out += &format!("  axis {a}: at {p}\n");
        }
        out
    })
}

/// `mcctl group home`: MC_GroupHome in `order` (empty: the configured one), waited for.
pub fn home(card: &Card, group: usize, order: Vec<Vec<usize>>, json: bool) -> Result<String> {
    let g = card.group(group)?;
    let stages: Vec<&[usize]> = order.iter().map(Vec::as_slice).collect();
    let homing = g.home(&stages)?;
    let run = super::wait_stepping(card, HOME_WAIT, |t| homing.wait(t))?;
    let axes = g.settings()?.map(|s| s.axes).unwrap_or_default();
    let st = card.statuses(&axes)?;
    Ok(if json {
        json!({
            "group": group,
            "stages": run,
            "axes": axes.iter().zip(&st).map(|(a, s)| json!({
                "axis": a,
                "homed": s.homed(),
                "position": s.actual_position,
            })).collect::<Vec<_>>(),
        })
        .to_string()
    } else {
        let mut out = format!("group {group}: homed in {run} stages\n");
        for (a, s) in axes.iter().zip(&st) {
            out += &format!("  axis {a}: at {}\n", s.actual_position);
        }
        out
    })
}

/// `mcctl group status`.
pub fn status(card: &Card, group: usize, json: bool) -> Result<String> {
    let g = card.group(group)?;
    let (state, _) = g.status()?;
    let settings = g.settings()?;
    let (axes, order) = settings.map(|s| (s.axes, s.home_order)).unwrap_or_default();
    Ok(if json {
        json!({
            "group": group,
            "state": state_name(state),
            "configured": !axes.is_empty(),
            "axes": axes,
            "home_order": order,
        })
        .to_string()
    } else if axes.is_empty() {
        format!("group {group}: {}, not configured\n", state_name(state))
    } else {
        let order = if order.is_empty() {
            "none".to_string()
        } else {
            order
                .iter()
                .map(|s| s.iter().map(usize::to_string).collect::<Vec<_>>().join(","))
                .collect::<Vec<_>>()
                .join(";")
        };
        format!(
            "group {group}: {}, card axes {:?}, home order {order}\n",
            state_name(state),
            axes
        )
    })
}

fn state_name(s: GroupState) -> String {
    format!("{s:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_parse_into_stages() {
        assert_eq!(
            parse_order("2;0,1").unwrap(),
            Order(vec![vec![2], vec![0, 1]])
        );
        assert_eq!(parse_order(" 1 , 0 ").unwrap(), Order(vec![vec![1, 0]]));
        assert_eq!(parse_order("2;").unwrap(), Order(vec![vec![2], vec![]]));
        let err = parse_order("2;x").unwrap_err();
        assert!(err.contains("`x`"), "{err}");
        assert!(parse_order("-1").is_err());
    }

    #[test]
    fn points_and_axes_parse_in_threes() {
        assert_eq!(
            parse_point("-5000, 0,1e3").unwrap(),
            Triple([-5000.0, 0.0, 1000.0])
        );
        assert!(parse_point("1,2").unwrap_err().contains("got 2"));
        assert!(parse_point("1,x,2").unwrap_err().contains("`x`"));
        assert!(parse_point("1,inf,2").is_err());
        assert_eq!(parse_axes("0,1,3").unwrap(), Triple([0, 1, 3]));
        assert!(parse_axes("0,-1,2").is_err());
        assert!(parse_axes("0,1,2,3").unwrap_err().contains("got 4"));
        assert_eq!(parse_list("3000").unwrap(), List(vec![3000.0]));
    }
}
