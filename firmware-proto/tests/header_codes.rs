//! The code enums generated from the header (`src/codes.rs`, `cargo xtask codegen`) against the
//! header itself, read here as text: every define of each kind is one variant, named after the
//! define (its name after the prefix, in CamelCase) and with its value, and there is no other
//! variant. A header edited without regenerating fails here as well as in `codegen --check`.

use firmware_proto::{
    AxisState, ConfigKind, Edge, EventKind, GroupState, HomingError, MasterSource, NackCode,
    Opcode, PvtEvent, ScopeEvent, ScopeMode, ScopeState, Signal, StopCategory, StopReason,
    SyncEvent, Trigger,
};
use std::fmt::Debug;

const HEADER: &str = include_str!("../include/mc_dpram.h");

/// Variants not named by the rule (the generator's exceptions).
const RENAMED: &[(&str, &str)] = &[
    ("MC_OP_ESTOP", "EStop"),
    ("MC_NACK_ESTOP_ACTIVE", "EStopActive"),
    ("MC_HOMING_ERR_LIMIT", "LimitReached"),
    ("MC_HOMING_ERR_DISTANCE", "DistanceExceeded"),
    ("MC_STOP_ESTOP_COMMAND", "EStopCommand"),
    ("MC_STOP_ESTOP_INPUT", "EStopInput"),
    ("MC_STOP_TIMEOUT", "StopTimeout"),
];

/// The header's integer defines whose names `keep` takes, with their values (`12u`, `12`,
/// `(1u << 3)`).
fn defines_where(keep: impl Fn(&str) -> bool) -> Vec<(String, u64)> {
    let mut out = Vec::new();
    for line in HEADER.lines() {
        let Some(rest) = line.trim().strip_prefix("#define ") else {
            continue;
        };
        let mut words = rest.split_whitespace();
        let name = words.next().unwrap();
        if !keep(name) {
            continue;
        }
        let value = rest[name.len()..].split("/*").next().unwrap().trim();
        let int = |s: &str| s.trim().trim_end_matches('u').parse::<u64>().unwrap();
        let v = match value.strip_prefix('(').and_then(|v| v.strip_suffix(')')) {
            Some(shift) => {
                let (a, b) = shift.split_once("<<").unwrap();
                int(a) << int(b)
            }
            None => int(value),
        };
        out.push((name.to_string(), v));
    }
    out
}

/// The header's integer defines whose names start with `prefix` (less `except`).
fn defines(prefix: &str, except: &[&str]) -> Vec<(String, u64)> {
    defines_where(|name| name.starts_with(prefix) && !except.iter().any(|e| name.starts_with(e)))
}

fn camel(stem: &str) -> String {
    stem.split('_')
        .map(|w| w[..1].to_string() + &w[1..].to_ascii_lowercase())
        .collect()
}

fn check<T: Debug + Copy>(
    all: &[T],
    value: impl Fn(T) -> u64,
    from_raw: impl Fn(u64) -> Option<T>,
    prefix: &str,
    strip: &str,
    except: &[&str],
) {
    check_defs(
        all,
        value,
        from_raw,
        &defines(prefix, except),
        prefix,
        strip,
    );
}

/// A kind whose defines share their prefix with other kinds': the defines named.
fn check_named<T: Debug + Copy>(
    all: &[T],
    value: impl Fn(T) -> u64,
    from_raw: impl Fn(u64) -> Option<T>,
    names: &[&str],
    strip: &str,
) {
    let defs = defines_where(|name| names.contains(&name));
    assert_eq!(defs.len(), names.len(), "{names:?}: {defs:?}");
    check_defs(all, value, from_raw, &defs, names[0], strip);
}

fn check_defs<T: Debug + Copy>(
    all: &[T],
    value: impl Fn(T) -> u64,
    from_raw: impl Fn(u64) -> Option<T>,
    defs: &[(String, u64)],
    what: &str,
    strip: &str,
) {
    assert!(!defs.is_empty(), "no {what} defines");
    assert_eq!(all.len(), defs.len(), "{what}: {all:?} against {defs:?}");
    for (name, v) in defs {
        let variant = from_raw(*v).unwrap_or_else(|| panic!("{name} = {v} has no variant"));
        assert_eq!(value(variant), *v);
        let expected = RENAMED
            .iter()
            .find(|(d, _)| d == name)
            .map_or_else(|| camel(&name[strip.len()..]), |(_, v)| v.to_string());
        assert_eq!(format!("{variant:?}"), expected, "{name}");
    }
}

#[test]
fn each_generated_enum_is_its_defines() {
    check(
        Opcode::ALL,
        |o| o as u64,
        |v| Opcode::from_raw(u16::try_from(v).ok()?),
        "MC_OP_",
        "MC_OP_",
        &[],
    );
    check(
        EventKind::ALL,
        |k| k as u64,
        |v| EventKind::from_raw(u16::try_from(v).ok()?),
        "MC_EV_",
        "MC_EV_",
        &[],
    );
    check(
        AxisState::ALL,
        |s| s as u64,
        |v| AxisState::from_raw(u32::try_from(v).ok()?),
        "MC_STATE_",
        "MC_STATE_",
        &[],
    );
    check(
        GroupState::ALL,
        |s| s as u64,
        |v| GroupState::from_raw(u32::try_from(v).ok()?),
        "MC_GROUP_",
        "MC_GROUP_",
        &["MC_GROUP_QUEUE_LEN", "MC_GROUP_HOME_"],
    );
    check(
        StopCategory::ALL,
        |c| c as u64,
        |v| StopCategory::from_raw(u32::try_from(v).ok()?),
        "MC_STOP_CAT_",
        "MC_STOP_",
        &[],
    );
    check(
        StopReason::ALL,
        |r| r as u64,
        |v| StopReason::from_raw(u32::try_from(v).ok()?),
        "MC_STOP_",
        "MC_STOP_",
        &["MC_STOP_CAT_"],
    );
    check(
        NackCode::ALL,
        |c| c as u64,
        |v| NackCode::from_raw(i32::try_from(v).ok()?),
        "MC_NACK_",
        "MC_NACK_",
        &[],
    );
    check(
        ConfigKind::ALL,
        |k| k as u64,
        |v| ConfigKind::from_raw(u32::try_from(v).ok()?),
        "MC_CONFIG_",
        "MC_CONFIG_",
        &[],
    );
    check(
        HomingError::ALL,
        |e| e as u64,
        |v| HomingError::from_raw(i32::try_from(v).ok()?),
        "MC_HOMING_ERR_",
        "MC_HOMING_ERR_",
        &[],
    );
    check(
        Signal::ALL,
        |s| s as u64,
        |v| Signal::from_raw(u32::try_from(v).ok()?),
        "MC_SIG_",
        "MC_SIG_",
        &[],
    );
    check(
        Trigger::ALL,
        |t| t as u64,
        |v| Trigger::from_raw(u32::try_from(v).ok()?),
        "MC_SCOPE_TRIG_",
        "MC_SCOPE_TRIG_",
        &[],
    );
    check(
        ScopeEvent::ALL,
        |e| e as u64,
        |v| ScopeEvent::from_raw(i32::try_from(v).ok()?),
        "MC_SCOPE_EV_",
        "MC_SCOPE_EV_",
        &[],
    );
    check(
        MasterSource::ALL,
        |m| m as u64,
        |v| MasterSource::from_raw(u32::try_from(v).ok()?),
        "MC_MASTER_",
        "MC_MASTER_",
        &[],
    );
    check(
        SyncEvent::ALL,
        |e| e as u64,
        |v| SyncEvent::from_raw(i32::try_from(v).ok()?),
        "MC_SYNC_",
        "MC_SYNC_",
        &[],
    );
    check(
        PvtEvent::ALL,
        |e| e as u64,
        |v| PvtEvent::from_raw(i32::try_from(v).ok()?),
        "MC_PVT_EV_",
        "MC_PVT_EV_",
        &[],
    );
    check_named(
        ScopeMode::ALL,
        |m| m as u64,
        |v| ScopeMode::from_raw(u32::try_from(v).ok()?),
        &["MC_SCOPE_ONE_SHOT", "MC_SCOPE_CONTINUOUS"],
        "MC_SCOPE_",
    );
    check_named(
        Edge::ALL,
        |e| e as u64,
        |v| Edge::from_raw(u32::try_from(v).ok()?),
        &["MC_SCOPE_RISING", "MC_SCOPE_FALLING", "MC_SCOPE_EITHER"],
        "MC_SCOPE_",
    );
    check_named(
        ScopeState::ALL,
        |s| s as u64,
        |v| ScopeState::from_raw(u32::try_from(v).ok()?),
        &[
            "MC_SCOPE_IDLE",
            "MC_SCOPE_WAITING",
            "MC_SCOPE_CAPTURING",
            "MC_SCOPE_DONE",
        ],
        "MC_SCOPE_",
    );
}
