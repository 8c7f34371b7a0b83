//! The register map's codes, generated from the header's `#define`s: the code enums of
//! firmware-proto (`firmware-proto/src/codes.rs`) and the C ABI's constants that are the same
//! codes under the C ABI's names (`cffi/src/codes.rs`, which cbindgen puts in motioncard.h).
//!
//! [`SETS`] says which defines make each set (every define with a prefix, or the block of
//! defines that starts at a given one) and what they become; the names, values and comments
//! are the header's. A value is what bindgen made of the define (read from the bindings it
//! generated), a doc comment is the define's trailing comment (a Rust variant must have one).

use std::collections::BTreeMap;

/// Which of the header's defines make a set.
#[derive(Debug, Clone, Copy)]
pub enum Select {
    /// Every define whose name starts with the prefix, in order of value.
    Prefix(&'static str),
    /// The define named `first` and the defines after it while their names start with
    /// `prefix`: the block ends at a blank line or another define (comment lines do not end
    /// it). In header order.
    Block {
        first: &'static str,
        prefix: &'static str,
    },
    /// One define.
    One(&'static str),
    /// The defines named, in this order: the kinds whose defines share no prefix or block
    /// with defines of another kind.
    List(&'static [&'static str]),
}

/// A code enum of firmware-proto (`code_enum!`).
#[derive(Debug, Clone, Copy)]
pub struct RustEnum {
    pub name: &'static str,
    pub repr: &'static str,
    pub doc: &'static str,
    /// The prefix taken off a define's name before it becomes a CamelCase variant.
    pub strip: &'static str,
}

/// The C ABI's constants of a set: the header's name with `from` replaced by `to`.
#[derive(Debug, Clone, Copy)]
pub struct CNames {
    pub from: &'static str,
    pub to: &'static str,
    /// Put before the first constant's own doc: where the C ABI uses the codes ("": the
    /// header's comments alone).
    pub intro: &'static str,
    /// The constants' Rust type when it is not bindgen's (`i32`: the `code` of an event).
    pub ty: Option<&'static str>,
}

/// One kind of code.
#[derive(Debug, Clone, Copy)]
pub struct Set {
    pub select: Select,
    pub rust: Option<RustEnum>,
    pub c: Option<CNames>,
}

/// Variants whose names are not the CamelCase of the define's name after the prefix.
pub const VARIANT_NAMES: &[(&str, &str)] = &[
    ("MC_OP_ESTOP", "EStop"),
    ("MC_NACK_ESTOP_ACTIVE", "EStopActive"),
    ("MC_HOMING_ERR_LIMIT", "LimitReached"),
    ("MC_HOMING_ERR_DISTANCE", "DistanceExceeded"),
    ("MC_STOP_ESTOP_COMMAND", "EStopCommand"),
    ("MC_STOP_ESTOP_INPUT", "EStopInput"),
    ("MC_STOP_TIMEOUT", "StopTimeout"),
];

/// C names that are not the prefix rule's.
pub const C_NAMES: &[(&str, &str)] = &[("MC_STOP_TIMEOUT", "MC_STOP_REASON_STOP_TIMEOUT")];

const fn rust(
    name: &'static str,
    repr: &'static str,
    doc: &'static str,
    strip: &'static str,
) -> Option<RustEnum> {
    Some(RustEnum {
        name,
        repr,
        doc,
        strip,
    })
}

const fn c(from: &'static str, to: &'static str, intro: &'static str) -> Option<CNames> {
    Some(CNames {
        from,
        to,
        intro,
        ty: None,
    })
}

/// C names of codes that go in `mc_event.code`, an `int32_t`.
const fn c_event_code(from: &'static str, to: &'static str, intro: &'static str) -> Option<CNames> {
    Some(CNames {
        from,
        to,
        intro,
        ty: Some("i32"),
    })
}

/// A set of C constants only.
const fn c_only(select: Select, c: Option<CNames>) -> Set {
    Set {
        select,
        rust: None,
        c,
    }
}

/// The sets, in the order they are generated (the opcodes last: in motioncard.h after the
/// codes of the typed calls).
pub const SETS: &[Set] = &[
    Set {
        select: Select::Prefix("MC_EV_"),
        rust: rust("EventKind", "u16", "Event kinds.", "MC_EV_"),
        c: c(
            "MC_EV_",
            "MC_EVENT_",
            "Event kind (`mc_event.kind`). `axis`, `seq`, `code` and `value` are the event's \
             fields; positions and distances in `value` are in user units (the rule of `mc_event`). `MC_EVENT_ACK` and \
             `MC_EVENT_NACK` are taken by the library, never delivered.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_STATE_DISABLED",
            prefix: "MC_STATE_",
        },
        rust: rust("AxisState", "u32", "PLCopen axis states.", "MC_STATE_"),
        c: c(
            "MC_STATE_",
            "MC_AXIS_STATE_",
            "Axis state (`mc_status.state`, the `code` of `MC_EVENT_STATE_CHANGED`): PLCopen's \
             states.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_GROUP_DISABLED",
            prefix: "MC_GROUP_",
        },
        rust: rust("GroupState", "u32", "PLCopen group states.", "MC_GROUP_"),
        c: c(
            "MC_GROUP_",
            "MC_GROUP_STATE_",
            "Group state (`mc_group_status.state`, the `code` of \
             `MC_EVENT_GROUP_STATE_CHANGED`): PLCopen's group states.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_STOP_CAT_0",
            prefix: "MC_STOP_CAT_",
        },
        rust: rust(
            "StopCategory",
            "u32",
            "IEC 60204-1 stop categories.",
            "MC_STOP_",
        ),
        c: c(
            "MC_STOP_CAT_",
            "MC_STOP_CATEGORY_",
            "IEC 60204-1 stop category (`mc_estop`, `mc_set_estop_input_category`, \
             `mc_safety_settings.limit_stop`).",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_STOP_NONE",
            prefix: "MC_STOP_",
        },
        rust: rust(
            "StopReason",
            "u32",
            "Why an axis's last motion ended (`AxisStatus::stop_reason`), after\n\
             `dmc_get_stop_reason` / `APS_get_stop_code`.",
            "MC_STOP_",
        ),
        c: c(
            "MC_STOP_",
            "MC_STOP_REASON_",
            "Stop reason (`mc_status.stop_reason`, `mc_stop_info.reason`, the `code` of \
             `MC_EVENT_SAFETY_STOP` and `MC_EVENT_AT_REST`). Safety reasons are \
             `MC_STOP_REASON_WATCHDOG` and above.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_FAULT_DAC_SATURATED",
            prefix: "MC_FAULT_",
        },
        rust: None,
        c: c(
            "MC_FAULT_",
            "MC_AXIS_FAULT_",
            "Fault bit of `mc_status.faults` (the `code` of `MC_EVENT_FAULT`).",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_CAP_SCURVE",
            prefix: "MC_CAP_",
        },
        rust: None,
        c: c(
            "MC_CAP_",
            "MC_CARD_CAP_",
            "Capability bit of `mc_card_info.capabilities`.",
        ),
    },
    Set {
        select: Select::Prefix("MC_MOTION_"),
        rust: None,
        c: c(
            "MC_MOTION_",
            "MC_MOTION_",
            "Motion bit of `mc_status.raw.motion_flags`.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_IO_LIMIT_POS",
            prefix: "MC_IO_",
        },
        rust: None,
        c: c("MC_IO_", "MC_IO_", "Bit of `mc_status.io`."),
    },
    Set {
        select: Select::One("MC_MAX_GROUPS"),
        rust: None,
        c: c(
            "MC_MAX_GROUPS",
            "MC_GROUP_COUNT",
            "Axes groups on a card (group numbers 0 .. `MC_GROUP_COUNT` - 1).",
        ),
    },
    Set {
        select: Select::One("MC_MAX_AXES"),
        rust: None,
        c: c(
            "MC_MAX_AXES",
            "MC_GROUP_MAX_AXES",
            "Most axes in one group (`mc_group_settings.axes`): as many as the card can have.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_ACCDEC_PRE",
            prefix: "MC_ACCDEC_",
        },
        rust: None,
        c: c(
            "MC_ACCDEC_",
            "MC_GROUP_ACCDEC_",
            "Acc/dec mode (`mc_group_settings.accdec`).",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_INTERP_EXACT",
            prefix: "MC_INTERP_",
        },
        rust: None,
        c: c(
            "MC_INTERP_",
            "MC_GROUP_INTERP_",
            "Arc interpolator (`mc_group_settings.interpolator`).",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_PLANE_XY",
            prefix: "MC_PLANE_",
        },
        rust: None,
        c: c(
            "MC_PLANE_",
            "MC_ARC_PLANE_",
            "Plane of an arc (`mc_group_move_circular`, path arcs).",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_CIRC_BY_CENTRE",
            prefix: "MC_CIRC_BY_",
        },
        rust: None,
        c: c(
            "MC_CIRC_BY_",
            "MC_ARC_BY_",
            "How an arc is given (`mc_arc.mode`): `aux` and `end` are in the coordinates of its \
             plane.",
        ),
    },
    Set {
        select: Select::Block {
            first: "MC_FILTER_NONE",
            prefix: "MC_FILTER_",
        },
        rust: None,
        c: c(
            "MC_FILTER_",
            "MC_FILTER_KIND_",
            "Acc/dec filter kind (`mc_filter.kind`).",
        ),
    },
    Set {
        select: Select::Prefix("MC_NACK_"),
        rust: rust(
            "NackCode",
            "i32",
            "Why a command was refused. One code per distinct fault.",
            "MC_NACK_",
        ),
        c: None,
    },
    Set {
        select: Select::Prefix("MC_CONFIG_"),
        rust: rust(
            "ConfigKind",
            "u32",
            "Layout 1.8: the configuration blocks `MC_OP_READ_CONFIG` reads back (`MC_CONFIG_*`).",
            "MC_CONFIG_",
        ),
        c: None,
    },
    // Homing (layout 1.5).
    c_only(
        Select::Block {
            first: "MC_HOMING_INDEX",
            prefix: "MC_HOMING_",
        },
        c(
            "MC_HOMING_",
            "MC_HOMING_FLAG_",
            "Bit of `mc_homing_settings.flags`.",
        ),
    ),
    Set {
        select: Select::Prefix("MC_HOMING_ERR_"),
        rust: rust(
            "HomingError",
            "i32",
            "Why homing failed (the `code` of [`EventKind::HomingFailed`]).",
            "MC_HOMING_ERR_",
        ),
        c: c_event_code(
            "MC_HOMING_ERR_",
            "MC_HOMING_ERROR_",
            "Why homing failed: the `code` of `MC_EVENT_HOMING_FAILED`.",
        ),
    },
    c_only(
        Select::One("MC_SET_POSITION_RELATIVE"),
        c(
            "MC_SET_POSITION_RELATIVE",
            "MC_SET_POSITION_RELATIVE",
            "`flags` of `mc_set_position`: the position moves by the argument (else it becomes \
             the argument).",
        ),
    ),
    // The continuous path (layout 1.6).
    c_only(
        Select::One("MC_PATH_LEN"),
        c("MC_PATH_LEN", "MC_PATH_SEGMENTS", ""),
    ),
    c_only(
        Select::One("MC_OUTPUTS"),
        c("MC_OUTPUTS", "MC_CARD_OUTPUTS", ""),
    ),
    c_only(
        Select::List(&[
            "MC_PATH_ABORTING",
            "MC_PATH_BUFFERED",
            "MC_PATH_BLEND_LOW",
            "MC_PATH_BLEND_PREVIOUS",
            "MC_PATH_BLEND_NEXT",
            "MC_PATH_BLEND_HIGH",
        ]),
        c(
            "MC_PATH_",
            "MC_PATH_BUFFER_",
            "`mc_path_segment.buffer` (PLCopen BufferMode): how a segment joins the one before \
             it.",
        ),
    ),
    c_only(
        Select::Prefix("MC_TM_"),
        c(
            "MC_TM_",
            "MC_PATH_TRANSITION_",
            "`mc_path_segment.transition` (PLCopen TransitionMode): how a blend is made. \
             `tolerance` is in user units of the first group axis.",
        ),
    ),
    c_only(
        Select::Prefix("MC_PATH_OUT_AT_"),
        c(
            "MC_PATH_OUT_AT_",
            "MC_OUTPUT_AT_",
            "When an output action fires (`mc_path_segment.at`, `mc_group_path_output`); \
             `distance` is in user units of the first group axis.",
        ),
    ),
    c_only(
        Select::Prefix("MC_PATHST_"),
        c(
            "MC_PATHST_",
            "MC_PATH_STATUS_",
            "Bit of `mc_group_status.path_flags`.",
        ),
    ),
    // Digital I/O, position compare and touch probes (layout 1.7).
    c_only(
        Select::One("MC_INPUTS"),
        c("MC_INPUTS", "MC_CARD_INPUTS", ""),
    ),
    c_only(
        Select::One("MC_COMPARE_CHANNELS"),
        c(
            "MC_COMPARE_CHANNELS",
            "MC_COMPARE_CHANNELS",
            "Compare channels of the card.",
        ),
    ),
    c_only(
        Select::One("MC_COMPARE_TABLE_LEN"),
        c("MC_COMPARE_TABLE_LEN", "MC_COMPARE_TABLE_LEN", ""),
    ),
    c_only(
        Select::One("MC_PROBE_CHANNELS"),
        c(
            "MC_PROBE_CHANNELS",
            "MC_PROBE_CHANNELS",
            "Touch-probe channels of the card.",
        ),
    ),
    c_only(
        Select::One("MC_PROBE_QUEUE"),
        c(
            "MC_PROBE_QUEUE",
            "MC_PROBE_QUEUE",
            "The length of `mc_probe_info.positions`.",
        ),
    ),
    c_only(
        Select::Block {
            first: "MC_CMP_FIRED",
            prefix: "MC_CMP_",
        },
        c_event_code(
            "MC_CMP_",
            "MC_COMPARE_",
            "The `code` of `MC_EVENT_COMPARE`.",
        ),
    ),
    c_only(
        Select::Block {
            first: "MC_IO_IDLE",
            prefix: "MC_IO_",
        },
        c(
            "MC_IO_",
            "MC_IO_STATE_",
            "`state` of a compare channel or a touch probe (`mc_compare_info.state`, \
             `mc_probe_info.state`).",
        ),
    ),
    c_only(
        Select::One("MC_PROBE_INDEX"),
        c(
            "MC_PROBE_INDEX",
            "MC_PROBE_INPUT_INDEX",
            "`mc_probe_trigger.input` that is not an input.",
        ),
    ),
    c_only(
        Select::List(&["MC_PROBE_RISING", "MC_PROBE_FALLING"]),
        c(
            "MC_PROBE_",
            "MC_PROBE_EDGE_",
            "Bit of `mc_probe_trigger.edges` (one or both).",
        ),
    ),
    // Synchronised motion: gearing, PT/PVT streams, camming (layout 1.7).
    Set {
        select: Select::Prefix("MC_MASTER_"),
        rust: rust(
            "MasterSource",
            "u32",
            "What a slave follows (the flags of `MC_OP_GEAR_IN` / `_POS`).",
            "MC_MASTER_",
        ),
        c: c(
            "MC_MASTER_",
            "MC_MASTER_",
            "What a slave follows (`master_kind` of `mc_gear_in`, `mc_gear_in_pos`, \
             `mc_cam_in`).",
        ),
    },
    c_only(
        Select::One("MC_AUX_ENCODERS"),
        c("MC_AUX_ENCODERS", "MC_AUX_ENCODERS", ""),
    ),
    Set {
        select: Select::Prefix("MC_SYNC_"),
        rust: rust(
            "SyncEvent",
            "i32",
            "The sub-cases of `MC_EV_SYNC` (its `code`).",
            "MC_SYNC_",
        ),
        c: c_event_code("MC_SYNC_", "MC_SYNC_", "The `code` of `MC_EVENT_SYNC`."),
    },
    c_only(Select::One("MC_PVT_LEN"), c("MC_PVT_LEN", "MC_PVT_LEN", "")),
    Set {
        select: Select::Prefix("MC_PVT_EV_"),
        rust: rust(
            "PvtEvent",
            "i32",
            "The sub-cases of `MC_EV_PVT` (its `code`).",
            "MC_PVT_EV_",
        ),
        c: c_event_code(
            "MC_PVT_EV_",
            "MC_PVT_EVENT_",
            "The `code` of `MC_EVENT_PVT`.",
        ),
    },
    c_only(
        Select::List(&["MC_CAM_CUBIC", "MC_CAM_PERIODIC"]),
        c(
            "MC_CAM_",
            "MC_CAM_",
            "Bit of the `flags` of `mc_cam_load_table`.",
        ),
    ),
    c_only(
        Select::One("MC_CAM_TABLES"),
        c(
            "MC_CAM_TABLES",
            "MC_CAM_TABLES",
            "Cam tables the card holds.",
        ),
    ),
    c_only(
        Select::One("MC_CAM_MAX_POINTS"),
        c(
            "MC_CAM_MAX_POINTS",
            "MC_CAM_MAX_POINTS",
            "Points of a cam table, at most.",
        ),
    ),
    // Layout 1.11: the servo law and filters.
    c_only(
        Select::List(&[
            "MC_SERVO_FFPIV",
            "MC_SERVO_PDPLUS",
            "MC_SERVO_PIDFF",
        ]),
        c(
            "MC_SERVO_",
            "MC_SERVO_",
            "`mc_axis_settings.servo_law`: the servo law an axis runs.",
        ),
    ),
    c_only(
        Select::One("MC_BIQUADS"),
        c(
            "MC_BIQUADS",
            "MC_BIQUADS",
            "Servo filters per axis (slots 0..`MC_BIQUADS`-1).",
        ),
    ),
    c_only(
        Select::List(&[
            "MC_BIQUAD_NONE",
            "MC_BIQUAD_NOTCH",
            "MC_BIQUAD_LOWPASS",
            "MC_BIQUAD_LEAD_LAG",
            "MC_BIQUAD_RAW",
        ]),
        c(
            "MC_BIQUAD_",
            "MC_BIQUAD_",
            "`mc_servo_filter.kind`: what a servo filter is.",
        ),
    ),
    // The scope (layout 1.8).
    c_only(
        Select::One("MC_SCOPE_CHANNELS"),
        c(
            "MC_SCOPE_CHANNELS",
            "MC_SCOPE_CHANNELS",
            "Channels per sample, at most (`mc_scope_settings.n_channels`).",
        ),
    ),
    c_only(
        Select::One("MC_SCOPE_RING_LEN"),
        c("MC_SCOPE_RING_LEN", "MC_SCOPE_RING_LEN", ""),
    ),
    Set {
        select: Select::Prefix("MC_SIG_"),
        rust: rust(
            "Signal",
            "u32",
            "What a scope channel samples (`MC_SIG_*`). Axis signals are the axis status's values, \
             group signals the group status's, card signals the card control block's words.",
            "MC_SIG_",
        ),
        c: c(
            "MC_SIG_",
            "MC_SCOPE_SIG_",
            "Scope signal: `mc_scope_settings.source[k]` is `MC_SCOPE_SIG_*` | index << 16. \
             Axis signals (1..18; index: the axis) are the axis status's values of the tick, \
             group signals (32..34; index: the group) the group status's, card signals (48..50; \
             index 0) the card's words.",
        ),
    },
    Set {
        select: Select::List(&["MC_SCOPE_ONE_SHOT", "MC_SCOPE_CONTINUOUS"]),
        rust: rust(
            "ScopeMode",
            "u32",
            "One shot or continuous (`MC_SCOPE_ONE_SHOT`, `MC_SCOPE_CONTINUOUS`).",
            "MC_SCOPE_",
        ),
        c: c("MC_SCOPE_", "MC_SCOPE_", "`mc_scope_settings.mode`."),
    },
    Set {
        select: Select::Prefix("MC_SCOPE_TRIG_"),
        rust: rust(
            "Trigger",
            "u32",
            "When the capture starts (`MC_SCOPE_TRIG_*`).",
            "MC_SCOPE_TRIG_",
        ),
        c: c(
            "MC_SCOPE_TRIG_",
            "MC_SCOPE_TRIG_",
            "`mc_scope_settings.trigger`: when the capture starts.",
        ),
    },
    Set {
        select: Select::List(&["MC_SCOPE_RISING", "MC_SCOPE_FALLING", "MC_SCOPE_EITHER"]),
        rust: rust(
            "Edge",
            "u32",
            "Which way a level or input trigger fires (`MC_SCOPE_RISING`…).",
            "MC_SCOPE_",
        ),
        c: c(
            "MC_SCOPE_",
            "MC_SCOPE_",
            "`mc_scope_settings.edge`: which way a level or input trigger fires.",
        ),
    },
    Set {
        select: Select::List(&[
            "MC_SCOPE_IDLE",
            "MC_SCOPE_WAITING",
            "MC_SCOPE_CAPTURING",
            "MC_SCOPE_DONE",
        ]),
        rust: rust(
            "ScopeState",
            "u32",
            "The scope's state (`scope_status.state`).",
            "MC_SCOPE_",
        ),
        c: c("MC_SCOPE_", "MC_SCOPE_STATE_", "`mc_scope_info.state`."),
    },
    Set {
        select: Select::Prefix("MC_SCOPE_EV_"),
        rust: rust(
            "ScopeEvent",
            "i32",
            "The codes of `MC_EV_SCOPE`.",
            "MC_SCOPE_EV_",
        ),
        c: c_event_code(
            "MC_SCOPE_EV_",
            "MC_SCOPE_EVENT_",
            "The `code` of `MC_EVENT_SCOPE`.",
        ),
    },
    Set {
        select: Select::Prefix("MC_OP_"),
        rust: rust("Opcode", "u16", "Command opcodes.", "MC_OP_"),
        c: c(
            "MC_OP_",
            "MC_OP_",
            "Opcode of a raw command (`mc_send_raw`).",
        ),
    },
];

/// A `#define` of the header.
#[derive(Debug, Clone, PartialEq)]
pub struct Define {
    pub name: String,
    /// Its trailing comment, continuation lines joined with spaces ("" when none).
    pub comment: String,
    /// Index of its block (blank lines separate blocks).
    pub block: usize,
    /// Set when a define that is not in the same run comes between it and the one before.
    pub run: usize,
}

/// The header's object-like `#define`s, in order.
pub fn defines(header: &str) -> Vec<Define> {
    let mut out = Vec::new();
    let (mut block, mut run) = (0, 0);
    let mut lines = header.lines().peekable();
    while let Some(line) = lines.next() {
        let t = line.trim();
        if t.is_empty() {
            block += 1;
            run += 1;
            continue;
        }
        let Some(rest) = t.strip_prefix("#define ") else {
            if !t.starts_with("/*") && !t.starts_with('*') {
                run += 1;
            }
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        // Function-like macros are not codes.
        if rest[name.len()..].starts_with('(') || name.is_empty() {
            continue;
        }
        let mut comment = String::new();
        if let Some(at) = rest.find("/*") {
            let mut text = rest[at + 2..].to_string();
            while !text.contains("*/") {
                let Some(next) = lines.next() else { break };
                let next = next.trim();
                let next = next.strip_prefix('*').unwrap_or(next);
                text.push(' ');
                text.push_str(next.trim());
            }
            let end = text.find("*/").unwrap_or(text.len());
            comment = text[..end].split_whitespace().collect::<Vec<_>>().join(" ");
        }
        out.push(Define {
            name,
            comment,
            block,
            run,
        });
    }
    out
}

/// `pub const NAME: TYPE = VALUE;` lines of bindgen's output: each name's type and value.
pub fn bindgen_values(bindings: &str) -> BTreeMap<String, (String, String)> {
    let mut out = BTreeMap::new();
    for line in bindings.lines() {
        let Some(rest) = line.trim().strip_prefix("pub const ") else {
            continue;
        };
        let Some((name, rest)) = rest.split_once(':') else {
            continue;
        };
        let Some((ty, value)) = rest.split_once('=') else {
            continue;
        };
        out.insert(
            name.trim().to_string(),
            (
                ty.trim().to_string(),
                value.trim().trim_end_matches(';').trim().to_string(),
            ),
        );
    }
    out
}

/// One code of a set.
#[derive(Debug, Clone, PartialEq)]
pub struct Code {
    pub name: String,
    pub comment: String,
    pub ty: String,
    pub value: String,
}

/// The defines a set selects, with their bindgen type and value.
pub fn select(
    set: &Set,
    defs: &[Define],
    values: &BTreeMap<String, (String, String)>,
) -> Result<Vec<Code>, String> {
    let code = |d: &Define| -> Result<Code, String> {
        let (ty, value) = values
            .get(&d.name)
            .ok_or(format!("bindgen made no constant of {}", d.name))?;
        Ok(Code {
            name: d.name.clone(),
            comment: d.comment.clone(),
            ty: ty.clone(),
            value: value.clone(),
        })
    };
    let mut out = Vec::new();
    match set.select {
        Select::Prefix(p) => {
            for d in defs.iter().filter(|d| d.name.starts_with(p)) {
                out.push(code(d)?);
            }
            let key = |c: &Code| c.value.parse::<u64>().unwrap_or(u64::MAX);
            out.sort_by_key(key);
        }
        Select::Block { first, prefix } => {
            let at = defs
                .iter()
                .position(|d| d.name == first)
                .ok_or(format!("the header has no {first}"))?;
            let (block, run) = (defs[at].block, defs[at].run);
            for d in &defs[at..] {
                if d.block != block || d.run != run || !d.name.starts_with(prefix) {
                    break;
                }
                out.push(code(d)?);
            }
        }
        Select::One(name) => {
            let d = defs
                .iter()
                .find(|d| d.name == name)
                .ok_or(format!("the header has no {name}"))?;
            out.push(code(d)?);
        }
        Select::List(names) => {
            for name in names {
                let d = defs
                    .iter()
                    .find(|d| d.name == *name)
                    .ok_or(format!("the header has no {name}"))?;
                out.push(code(d)?);
            }
        }
    }
    if out.is_empty() {
        return Err(format!("{:?} selects no define", set.select));
    }
    Ok(out)
}

/// CamelCase of an upper-case snake name: `GROUP_MOVE_PTP` -> `GroupMovePtp`, `CAT_0` ->
/// `Cat0`.
pub fn camel(stem: &str) -> String {
    stem.split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut cs = w.chars();
            let first = cs.next().expect("not empty");
            first.to_string() + &cs.as_str().to_ascii_lowercase()
        })
        .collect()
}

/// The Rust variant of a define.
pub fn variant_name(e: &RustEnum, define: &str) -> String {
    VARIANT_NAMES
        .iter()
        .find(|(d, _)| *d == define)
        .map(|(_, v)| v.to_string())
        .unwrap_or_else(|| camel(define.strip_prefix(e.strip).unwrap_or(define)))
}

/// The C ABI's name of a define of a set.
pub fn c_name(c: &CNames, define: &str) -> Result<String, String> {
    if let Some((_, n)) = C_NAMES.iter().find(|(d, _)| *d == define) {
        return Ok(n.to_string());
    }
    let stem = define
        .strip_prefix(c.from)
        .ok_or(format!("{define} does not start with {}", c.from))?;
    Ok(format!("{}{stem}", c.to))
}

/// A define's comment as a doc paragraph: first letter capitalised, a full stop at the end,
/// names (anything with `_`, `[` or `->`) in code spans, each word passed through `rename`.
pub fn doc_text(comment: &str, rename: &dyn Fn(&str) -> String) -> String {
    let mut words = Vec::new();
    for w in comment.split_whitespace() {
        // Keep leading "(" and trailing punctuation outside the code span.
        let start = w.find(|c: char| c != '(').unwrap_or(w.len());
        let end = w
            .rfind(|c: char| !matches!(c, ',' | '.' | ';' | ':' | ')'))
            .map_or(start, |i| i + 1)
            .max(start);
        let (pre, core, post) = (&w[..start], &w[start..end], &w[end..]);
        let core = rename(core);
        let code = core.contains('_') || core.contains('[') || core.contains('*');
        if code && !core.contains('`') {
            words.push(format!("{pre}`{core}`{post}"));
        } else {
            words.push(format!("{pre}{core}{post}"));
        }
    }
    let mut text = words.join(" ");
    if let Some(first) = text.chars().next() {
        if first.is_ascii_lowercase() {
            text.replace_range(..1, &first.to_ascii_uppercase().to_string());
        }
    }
    if !text.is_empty() && !text.ends_with(['.', '!', '?']) {
        text.push('.');
    }
    text
}

/// `///` lines of a text wrapped within `width` columns, after `indent`.
fn doc_lines(text: &str, indent: &str, width: usize) -> String {
    let mut out = String::new();
    for para in text.split('\n') {
        let mut line = String::new();
        for w in para.split_whitespace() {
            if !line.is_empty() && indent.len() + 4 + line.len() + 1 + w.len() > width {
                out.push_str(&format!("{indent}/// {line}\n"));
                line.clear();
            }
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(w);
        }
        if line.is_empty() {
            out.push_str(&format!("{indent}///\n"));
        } else {
            out.push_str(&format!("{indent}/// {line}\n"));
        }
    }
    out
}

const GENERATED: &str =
    "Generated by `cargo xtask codegen` from firmware-proto/include/mc_dpram.h. Do not edit.";

/// `firmware-proto/src/codes.rs`: the code enums.
pub fn rust_enums(header: &str, bindings: &str) -> Result<String, String> {
    let defs = defines(header);
    let values = bindgen_values(bindings);
    let mut out = format!(
        "//! {GENERATED}\n//!\n\
         //! The code enums whose variants are the header's `#define`s of one kind: the variant is\n\
         //! the define's name after its prefix in CamelCase, its doc the define's comment, its\n\
         //! value the define's. [`crate::wire`] re-exports them.\n\nuse crate::raw;\n"
    );
    for set in SETS {
        let Some(e) = &set.rust else { continue };
        let codes = select(set, &defs, &values)?;
        out.push_str(&format!(
            "\ncode_enum! {{\n{}    {}: {} {{\n",
            doc_lines(e.doc, "    ", 100),
            e.name,
            e.repr
        ));
        for code in &codes {
            if code.comment.is_empty() {
                return Err(format!(
                    "{} has no comment in the header: its comment is the doc of {}::{}",
                    code.name,
                    e.name,
                    variant_name(e, &code.name)
                ));
            }
            out.push_str(&doc_lines(
                &doc_text(&code.comment, &|w| w.to_string()),
                "        ",
                100,
            ));
            out.push_str(&format!(
                "        {} = raw::{},\n",
                variant_name(e, &code.name),
                code.name
            ));
        }
        out.push_str("    }\n}\n");
    }
    Ok(out)
}

/// The C ABI's names of the header's names and `PREFIX_*` patterns that the sets rename.
pub fn c_renames(
    defs: &[Define],
    values: &BTreeMap<String, (String, String)>,
) -> Result<BTreeMap<String, String>, String> {
    let mut map = BTreeMap::new();
    for set in SETS {
        let Some(c) = &set.c else { continue };
        // A pattern names every define with the prefix: only a set of all of them renames it.
        if matches!(set.select, Select::Prefix(_) | Select::Block { .. }) {
            map.insert(format!("{}*", c.from), format!("{}*", c.to));
        }
        for code in select(set, defs, values)? {
            map.insert(code.name.clone(), c_name(c, &code.name)?);
        }
    }
    Ok(map)
}

/// `cffi/src/codes.rs`: the C ABI's constants of the sets that have C names.
pub fn c_constants(header: &str, bindings: &str) -> Result<String, String> {
    let defs = defines(header);
    let values = bindgen_values(bindings);
    let renames = c_renames(&defs, &values)?;
    let rename = |w: &str| renames.get(w).cloned().unwrap_or_else(|| w.to_string());
    let mut out = format!(
        "//! {GENERATED}\n//!\n\
         //! The C ABI's constants that are codes of the register map, under the C ABI's names: the\n\
         //! header's define, its prefix replaced (`MC_STATE_` -> `MC_AXIS_STATE_`, `MC_EV_` ->\n\
         //! `MC_EVENT_`, ...), with the define's value and comment. Literals, so that cbindgen\n\
         //! writes them into motioncard.h. The rules are in `xtask/src/codes.rs`.\n"
    );
    let mut named = std::collections::BTreeSet::new();
    for set in SETS {
        let Some(c) = &set.c else { continue };
        let codes = select(set, &defs, &values)?;
        for (i, code) in codes.iter().enumerate() {
            let name = c_name(c, &code.name)?;
            if !named.insert(name.clone()) {
                return Err(format!("two sets make {name}"));
            }
            let own = doc_text(&code.comment, &rename);
            let intro = if i == 0 { c.intro } else { "" };
            let doc = match (intro.is_empty(), own.is_empty()) {
                (false, true) => intro.to_string(),
                (false, false) => format!("{intro}\n\n{own}"),
                (true, false) => own,
                (true, true) => {
                    return Err(format!(
                        "{} has no comment in the header: its comment is the doc of {name}",
                        code.name
                    ))
                }
            };
            out.push('\n');
            out.push_str(&doc_lines(&doc, "", 100));
            out.push_str(&format!(
                "pub const {name}: {} = {};\n",
                c.ty.unwrap_or(&code.ty),
                code.value
            ));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "\
/* Things */
#define MC_X_ONE 1u /* the first
                     * of them */
#define MC_X_TWO (1u << 1)
/* between */
#define MC_X_THREE 3u /* third, see MC_X_ONE and MC_Y_* */
#define MC_Y_A 7u /* a */

#define MC_X_FOUR 4u /* not in the block of MC_X_ONE */
#define MC_F(a) (a)
";

    const BINDINGS: &str = "pub const MC_X_ONE: u32 = 1;\npub const MC_X_TWO: u32 = 2;\n\
        pub const MC_X_THREE: u32 = 3;\npub const MC_Y_A: u32 = 7;\npub const MC_X_FOUR: u32 = 4;\n";

    #[test]
    fn defines_and_their_comments() {
        let d = defines(HEADER);
        let names: Vec<&str> = d.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(
            names,
            ["MC_X_ONE", "MC_X_TWO", "MC_X_THREE", "MC_Y_A", "MC_X_FOUR"]
        );
        assert_eq!(d[0].comment, "the first of them");
        assert_eq!(d[1].comment, "");
        assert_eq!(d[2].block, d[0].block);
        assert_ne!(d[4].block, d[0].block);
    }

    #[test]
    fn blocks_and_prefixes_select_their_defines() {
        let (d, v) = (defines(HEADER), bindgen_values(BINDINGS));
        let names = |s: Select| -> Vec<String> {
            let set = Set {
                select: s,
                rust: None,
                c: None,
            };
            select(&set, &d, &v)
                .unwrap()
                .into_iter()
                .map(|c| c.name)
                .collect()
        };
        assert_eq!(
            names(Select::Block {
                first: "MC_X_ONE",
                prefix: "MC_X_"
            }),
            ["MC_X_ONE", "MC_X_TWO", "MC_X_THREE"]
        );
        assert_eq!(
            names(Select::Prefix("MC_X_")),
            ["MC_X_ONE", "MC_X_TWO", "MC_X_THREE", "MC_X_FOUR"]
        );
        assert_eq!(names(Select::One("MC_Y_A")), ["MC_Y_A"]);
        assert_eq!(
            names(Select::List(&["MC_X_THREE", "MC_X_ONE"])),
            ["MC_X_THREE", "MC_X_ONE"]
        );
    }

    #[test]
    fn names_and_docs() {
        assert_eq!(camel("GROUP_MOVE_PTP"), "GroupMovePtp");
        assert_eq!(camel("CAT_0"), "Cat0");
        let stop = SETS
            .iter()
            .find_map(|s| s.rust.filter(|e| e.name == "StopReason"))
            .unwrap();
        assert_eq!(variant_name(&stop, "MC_STOP_TIMEOUT"), "StopTimeout");
        assert_eq!(variant_name(&stop, "MC_STOP_CMD_RING"), "CmdRing");
        let ev = CNames {
            from: "MC_EV_",
            to: "MC_EVENT_",
            intro: "",
            ty: None,
        };
        assert_eq!(c_name(&ev, "MC_EV_AT_REST").unwrap(), "MC_EVENT_AT_REST");
        assert!(c_name(&ev, "MC_OP_NOP").is_err());
        assert_eq!(
            doc_text(
                "code: MC_STOP_* reason (axis_config[axis]), see MC_X.",
                &|w| { w.replace("MC_STOP_", "MC_STOP_REASON_") }
            ),
            "Code: `MC_STOP_REASON_*` reason (`axis_config[axis]`), see `MC_X`."
        );
    }

    fn workspace_file(rel: &str) -> String {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        std::fs::read_to_string(root.join(rel)).unwrap()
    }

    /// The checked-in files are what the header and the checked-in bindings give (the same
    /// check as `codegen --check`, without libclang).
    #[test]
    fn the_checked_in_codes_are_the_headers() {
        let header = workspace_file("firmware-proto/include/mc_dpram.h");
        let bindings = workspace_file("firmware-proto/src/raw.rs");
        assert!(
            rust_enums(&header, &bindings).unwrap()
                == workspace_file("firmware-proto/src/codes.rs"),
            "firmware-proto/src/codes.rs is stale: run cargo xtask codegen"
        );
        assert!(
            c_constants(&header, &bindings).unwrap() == workspace_file("cffi/src/codes.rs"),
            "cffi/src/codes.rs is stale: run cargo xtask codegen"
        );
    }

    #[test]
    fn an_enum_variant_needs_a_comment() {
        let header = workspace_file("firmware-proto/include/mc_dpram.h");
        let bindings = workspace_file("firmware-proto/src/raw.rs");
        let nop = "/* does nothing but answer: the round-trip probe */";
        assert!(header.contains(nop));
        let err = rust_enums(&header.replace(nop, ""), &bindings).unwrap_err();
        assert!(err.contains("MC_OP_NOP has no comment"), "{err}");
    }
}
