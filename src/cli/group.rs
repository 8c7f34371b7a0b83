//! `mcctl group home|status`: axes groups (layout 1.11) over the SDK's [`Group::home`] and
//! [`Group::settings`]. A group's axes are its group axis indices (0: its X, its first axis),
//! not card axes.
//!
//! [`Group::home`]: crate::Group::home
//! [`Group::settings`]: crate::Group::settings

use super::on_card;
use crate::{Card, GroupState, Result};
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
}
