//! Card configuration files (layout 1.8): every setting the card holds, in TOML.
//!
//! [`Card::save_config`] writes what the card holds, read back from the card
//! (`MC_OP_READ_CONFIG`), never the SDK's memory; [`Card::load_config`] checks a whole file
//! first, with the card's own checks (`card_firmware::host` and the functions beside
//! each block's type), and applies nothing if any value is wrong: the error names the key
//! (`axis.2.ffpiv.kp`) and its line. Then it applies the sections that differ from what the
//! card holds, reads the card back and compares. [`Card::diff_config`] lists, key by key, where
//! a file and the card differ.
//!
//! The file is in the card's units (counts, seconds, volts, Hz, µs), with the names of the
//! register map's fields (`mc_dpram.h`) and of the SDK's settings:
//!
//! ```toml
//! [card]            # servo_rate_hz
//! [safety]          # watchdog_timeout_us, estop_input_category, max_stop_time_us
//! [io]              # polarity, rise_events, fall_events (bit i: input i), debounce (ticks)
//! [axis.N]          # scale, servo_law ("ffpiv" | "pdplus" | "pidff"), dac_limit_v, windows, jog limits,
//!                   # modulo (a rotary axis's period, user units; 0: linear; layout 1.10)
//! [axis.N.ffpiv]    # kp, ki, kv, kvff, kaff, vel_filter_hz
//! [axis.N.pdplus]   # kp, kd, kv, ka, kc, tau, ke, umax: only with servo_law = "pdplus"
//! [axis.N.pidff]    # kp, ki, kd, kvff, kaff, friction, friction_deadband, d_filter_hz: only
//!                   # with servo_law = "pidff" (layout 1.11)
//! [axis.N.filter]   # rapid_kind, rapid_tau, cutting_kind, cutting_tau, jog_kind, jog_tau
//! [axis.N.safety]   # soft/hard limits, alarm and encoder checks, following error, stop ramp
//! [axis.N.homing]   # method, index, move_to_home, velocities, limits
//! [axis.N.compensation] # backlash, bound, ramp_velocity, ramp_acceleration, bidirectional,
//!                   # points ([position, forward, reverse] each, user units): layout 1.9
//! [group.N]         # axes, accdec, interpolator, tolerance: all four, or none (not configured)
//! [group.N.path]    # lookahead, low_water, accel, jerk, vmax, amax, jmax (one per group axis),
//!                   # plan_period (may be left out: 0, the card's default)
//! [gantry.N]        # master, slaves, kp, ki, skew_limit, offsets (one per slave, the master's
//!                   # user units; may be left out: 0 each): a formed gantry, layout 1.10
//! [axis.N.biquad.K] # kind ("none" | "notch" | "lowpass" | "lead_lag" | "raw") and its keys:
//!                   # freq_hz, damping, depth_db (notch); freq_hz, damping (lowpass); freq_hz,
//!                   # freq2_hz (lead_lag); b0, b1, b2, a1, a2 (raw): the servo output's
//!                   # filter in slot K (0..4), layout 1.11
//! [analog_input.N]  # cutoff_hz, threshold, hysteresis, rise_event, fall_event (layout 1.11)
//! [pso]             # output ("off" | "dac" | "pwm"), group, channel, pwm_hz (pwm only), gate,
//!                   # min, max, v_ref (counts/s), filter_hz: the path-speed output, layout 1.11
//! ```
//!
//! A file may name any subset of the sections and of the axes and groups: what it does not
//! name is left as the card holds it. Within a section every key is needed (but
//! `plan_period`, which files saved before it existed lack); an unknown key, a
//! value of the wrong type, an axis or group the card does not have, or a value the card would
//! refuse is an error. `save` writes every section, in a fixed order, each float in Rust's
//! shortest representation that reads back to the same bits: load, then save, gives the same
//! bytes.
//!
//! A group configuration cannot be removed (the card has no command for it): a configured
//! group the file leaves unconfigured stays configured.
//!
//! The filters of `[axis.N.biquad.K]` are designed at the file's servo rate (else the card's),
//! as are the axis's filters the file does not name: a servo rate at which one of those would
//! not design (above the new Nyquist frequency) is refused. A slot the file does not name is
//! left as it is. The spare DAC outputs have no settings, only a value, and are not in the
//! file (as the digital outputs are not): a file does not drive an output. `[pso]` is started
//! after the groups (it runs on one); one the card runs with the same settings is left
//! running, `output = "off"` stops it.
//!
//! A `[gantry.N]` is formed last, after the axes and groups, its axes at rest (all powered or
//! all disabled). A gantry the card holds with the file's settings is left as it is (its
//! squaring kept); one the card holds with other settings is refused (dissolve it first: a
//! file never breaks a squared bridge), and a gantry the file does not name stays formed.

mod sections;
mod text;

pub(crate) use sections::user_modulo;
pub use sections::{
    AccDecName, AnalogInputSection, AxisSafetySection, AxisSection, BiquadName, BiquadSection,
    CardSection, CompensationSection, Config, ConfigDifference, FfpivSection, FilterName,
    FilterSection, GantrySection, GroupSection, HomingSection, InterpolatorName, IoSection,
    PathSection, PdPlusSection, PidffSection, PsoOutputName, PsoSection, SafetySection, ServoLaw,
    CONFIG_HEADER,
};
use text::{file_error, line_of_key, read_file};
pub use text::{ECHO_CHARS, MAX_CONFIG_BYTES};

use crate::card::{Card, SCALE_RANGE};
use crate::error::{nack_reason, Error, Result};
use card_firmware::host::validate_path_config;
use card_firmware::host::AxisSafetyConfig;
use card_firmware::host::HomingConfig;
use card_firmware::host::IoConfig;
use card_firmware::host::SafetyConfig;
use card_firmware::host::{analog_input_nack, design_biquad, pso_nack};
use card_firmware::host::{decode_axis_filter, validate_axis_config, validate_group_config};
use firmware_proto::Mem as _;
use firmware_proto::{
    layout, raw, AxisConfig, AxisState, ConfigKind, GroupState, NackCode, INPUTS, MAX_AXES,
    MAX_GROUPS,
};
use serde::de::DeserializeOwned;
use serde::Serialize;

// ----- checks ----------------------------------------------------------------------------

/// A refusal of the checks: the key (dotted) and what is wrong.
type Refusal = (String, String);

fn nack_text(c: NackCode) -> String {
    format!("the card would refuse it: {} ({c:?})", nack_reason(c))
}

/// The first leaf of `bad` whose value taken from `good` makes `check` pass (relative dotted
/// path), or `None` when no single value does.
fn blame<S: Serialize + DeserializeOwned>(
    bad: &S,
    good: &S,
    check: impl Fn(&S) -> std::result::Result<(), NackCode>,
) -> Option<String> {
    let bad_v = toml::Value::try_from(bad).ok()?;
    let good_v = toml::Value::try_from(good).ok()?;
    let mut leaves = Vec::new();
    collect_leaves(&bad_v, &mut Vec::new(), &mut leaves);
    for path in leaves {
        let Some(g) = get_path(&good_v, &path) else {
            continue;
        };
        let mut v = bad_v.clone();
        if let Some(slot) = get_path_mut(&mut v, &path) {
            *slot = g.clone();
        }
        if let Ok(s) = v.try_into::<S>() {
            if check(&s).is_ok() {
                return Some(path.join("."));
            }
        }
    }
    None
}

fn collect_leaves(v: &toml::Value, at: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                at.push(k.clone());
                collect_leaves(v, at, out);
                at.pop();
            }
        }
        toml::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                at.push(i.to_string());
                collect_leaves(v, at, out);
                at.pop();
            }
        }
        _ => out.push(at.clone()),
    }
}

fn get_path<'a>(v: &'a toml::Value, path: &[String]) -> Option<&'a toml::Value> {
    path.iter().try_fold(v, |v, p| match v {
        toml::Value::Table(t) => t.get(p),
        toml::Value::Array(a) => a.get(p.parse::<usize>().ok()?),
        _ => None,
    })
}

fn get_path_mut<'a>(v: &'a mut toml::Value, path: &[String]) -> Option<&'a mut toml::Value> {
    path.iter().try_fold(v, |v, p| match v {
        toml::Value::Table(t) => t.get_mut(p),
        toml::Value::Array(a) => a.get_mut(p.parse::<usize>().ok()?),
        _ => None,
    })
}

/// Run `check` on a section; on a refusal name the key (through [`blame`] against `good`).
fn refuse<S: Serialize + DeserializeOwned>(
    prefix: &str,
    bad: &S,
    good: &S,
    check: impl Fn(&S) -> std::result::Result<(), NackCode>,
) -> std::result::Result<(), Refusal> {
    let Err(code) = check(bad) else {
        return Ok(());
    };
    let key = match blame(bad, good, &check) {
        Some(k) => format!("{prefix}.{k}"),
        None => prefix.to_string(),
    };
    Err((key, nack_text(code)))
}

/// The number in a section's key: `"3"` (canonical decimal) below `count`.
fn index_key(kind: &str, key: &str, count: usize) -> std::result::Result<usize, Refusal> {
    match key.parse::<usize>() {
        Ok(i) if i.to_string() == key && i < count => Ok(i),
        _ => Err((
            format!("{kind}.{key}"),
            format!(
                "no such {kind}: the card has {count} ({kind}.0 to {kind}.{})",
                count - 1
            ),
        )),
    }
}

/// What the checks need to know of the card.
struct Context<'a> {
    num_axes: usize,
    host_period_us: u32,
    card: &'a Config,
    axis_states: Vec<AxisState>,
    group_states: Vec<GroupState>,
}

/// The reference values the blame takes: the card's reset values (PD+: the die bonder's).
fn good_axis() -> AxisSection {
    // The reset blocks, with the PD+ section of the die bonder (the check of an FFPIV axis
    // drops it).
    AxisSection::from_blocks(
        &AxisConfig {
            servo_law: raw::MC_SERVO_PDPLUS,
            ..AxisConfig::default()
        },
        &crate::nurbs::die_bonder_pdplus(0),
        &firmware_proto::AxisPidff::default(),
        &card_firmware::host::FilterConfig::default().to_block(),
        &AxisSafetyConfig::default().to_block(),
        &firmware_proto::AxisHoming::default(),
    )
}

/// Check `file` against the card, section by section in the order the card would apply them;
/// the first refusal names its key.
fn check(file: &Config, cx: &Context<'_>) -> std::result::Result<(), Refusal> {
    let rate = check_card(file, cx)?;
    let max_stop = check_safety(file, cx)?;
    check_io(file)?;
    let good = good_axis();
    for (key, ax) in &file.axis {
        check_axis(key, ax, &good, cx, rate, max_stop)?;
    }
    check_biquads_at_rate(file, cx, rate)?;
    check_stop_ramps(file, cx, max_stop)?;
    check_groups(file, cx, rate)?;
    check_gantries(file, cx)?;
    check_analog_inputs(file, rate)?;
    check_pso(file, cx, rate)
}

/// `[axis.N.biquad.K]` (prefix `p`: `axis.N.biquad.K`): the keys of its kind and no other,
/// then the card's check and design at servo rate `rate`, the refusal naming its key.
fn check_biquad(p: &str, b: &BiquadSection, rate: u32) -> std::result::Result<(), Refusal> {
    for (key, needed, present) in b.keys() {
        if needed != present {
            let kind = toml::Value::try_from(b.kind).map_or(String::new(), |v| v.to_string());
            let why = if needed {
                format!("a filter of kind {kind} needs `{key}`")
            } else {
                format!("`{key}` is not a key of a filter of kind {kind}")
            };
            return Err((format!("{p}.{key}"), why));
        }
    }
    let Some(spec) = b.spec() else {
        return Ok(());
    };
    // The reference each value is blamed against: a filter of the kind the card takes.
    let f = f64::from(rate) / 20.0;
    let good = BiquadSection::from_spec(Some(&match spec.kind {
        firmware_proto::cmd::BiquadKind::Notch => crate::BiquadSpec::notch(f, 0.5, -20.0),
        firmware_proto::cmd::BiquadKind::LowPass => crate::BiquadSpec::low_pass(f, 0.7),
        firmware_proto::cmd::BiquadKind::LeadLag => crate::BiquadSpec::lead_lag(f, 2.0 * f),
        firmware_proto::cmd::BiquadKind::Raw => crate::BiquadSpec::raw([1.0, 0.0, 0.0, 0.0, 0.0]),
    }));
    refuse(p, b, &good, |s| {
        s.spec().map_or(Ok(()), |spec| {
            design_biquad(&spec, f64::from(rate)).map(|_| ())
        })
    })
}

/// The axes' filters the file does not name, as the card holds them, designed at the file's
/// servo rate: a rate at which one would not design is refused.
fn check_biquads_at_rate(
    file: &Config,
    cx: &Context<'_>,
    rate: u32,
) -> std::result::Result<(), Refusal> {
    if file.card.is_none() || file.card == cx.card.card {
        return Ok(());
    }
    for (key, ax) in &cx.card.axis {
        for (k, b) in &ax.biquad {
            if file.axis.get(key).is_some_and(|f| f.biquad.contains_key(k)) {
                continue;
            }
            if let Some(Err(code)) = b
                .spec()
                .map(|spec| design_biquad(&spec, f64::from(rate)).map(|_| ()))
            {
                return Err((
                    "card.servo_rate_hz".into(),
                    format!(
                        "axis {key}'s filter in slot {k} ({:?} at {} Hz) cannot run at {rate} \
                         Hz: {} (set or clear [axis.{key}.biquad.{k}] in the file)",
                        b.kind,
                        b.freq_hz.unwrap_or(0.0),
                        nack_text(code)
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// `[analog_input.N]`: the card's decoding of the command and its check at the servo rate.
fn check_analog_inputs(file: &Config, rate: u32) -> std::result::Result<(), Refusal> {
    use firmware_proto::cmd::IoCmd;
    let good = AnalogInputSection::from(&crate::AnalogInputSettings::default());
    for (key, a) in &file.analog_input {
        let i = index_key("analog_input", key, firmware_proto::ANALOG_INPUTS)?;
        refuse(&format!("analog_input.{i}"), a, &good, |s| {
            let c = IoCmd::AnalogInput(s.command(i)).command(0);
            match IoCmd::decode(firmware_proto::Opcode::AnalogInput, c.flags, &c.args) {
                Ok(IoCmd::AnalogInput(a)) => analog_input_nack(&a, rate),
                Ok(_) => Err(NackCode::BadConfig),
                Err(e) => Err(e.nack),
            }
        })?;
    }
    Ok(())
}

/// `[pso]`: the keys of its output and no other, its group configured after the file, the
/// card's decoding of the command and its check at the servo rate.
fn check_pso(file: &Config, cx: &Context<'_>, rate: u32) -> std::result::Result<(), Refusal> {
    use firmware_proto::cmd::IoCmd;
    let Some(pso) = &file.pso else {
        return Ok(());
    };
    for (key, needed, present) in pso.keys() {
        if needed != present {
            let out = toml::Value::try_from(pso.output).map_or(String::new(), |v| v.to_string());
            let why = if needed {
                format!("a PSO with output = {out} needs `{key}`")
            } else {
                format!("`{key}` is not a key of a PSO with output = {out}")
            };
            return Err((format!("pso.{key}"), why));
        }
    }
    let Some((g, _)) = pso.settings() else {
        return Ok(());
    };
    let configured = |key: &str| {
        file.group
            .get(key)
            .and_then(|s| s.axes.as_ref())
            .or_else(|| cx.card.group.get(key).and_then(|s| s.axes.as_ref()))
            .is_some()
    };
    if g >= MAX_GROUPS || !configured(&g.to_string()) {
        return Err(("pso.group".into(), nack_text(NackCode::PsoGroup)));
    }
    let good = PsoSection {
        output: pso.output,
        group: pso.group,
        channel: Some(0),
        pwm_hz: pso.pwm_hz.map(|_| 1000.0),
        gate: Some(if pso.channel == Some(1) { 2 } else { 1 }),
        min: Some(0.0),
        max: Some(if pso.output == PsoOutputName::Pwm {
            1.0
        } else {
            10.0
        }),
        v_ref: Some(1e4),
        filter_hz: Some(0.0),
    };
    refuse("pso", pso, &good, |s| {
        let Some((_, p)) = s.settings() else {
            return Ok(());
        };
        let mut c = IoCmd::Pso(PsoSection::command(&p)).command(0);
        // An index beyond a byte stays one the card does not have.
        for (arg, v) in [(0, s.channel), (1, s.gate)] {
            if v.is_some_and(|v| v > u32::from(u8::MAX)) {
                c.args[arg] = f64::from(v.unwrap_or(0));
            }
        }
        match IoCmd::decode(firmware_proto::Opcode::Pso, c.flags, &c.args) {
            Ok(IoCmd::Pso(p)) => pso_nack(&p, rate),
            Ok(_) => Err(NackCode::BadConfig),
            Err(e) => Err(e.nack),
        }
    })
}

/// `[gantry.N]`: what [`Card::gantry_at`] and the card check, each refusal naming its key;
/// the card's gantry with other settings refused; the members at rest, in no other gantry,
/// the slaves in no group (the groups after the file).
fn check_gantries(file: &Config, cx: &Context<'_>) -> std::result::Result<(), Refusal> {
    use firmware_proto::cmd::{GANTRY_KI_MAX, GANTRY_KP_MAX, GANTRY_MAX_SLAVES, MAX_GANTRIES};
    let n = cx.num_axes;
    // Which gantry each axis is in: the card's gantries the file leaves as they are.
    let mut member = [None::<usize>; MAX_AXES];
    for (key, g) in &cx.card.gantry {
        if !file.gantry.contains_key(key) {
            for &a in std::iter::once(&g.master).chain(&g.slaves) {
                member[a as usize % MAX_AXES] = key.parse().ok();
            }
        }
    }
    // Which group each axis is in after the file.
    let mut grouped = [None::<usize>; MAX_AXES];
    for g in 0..MAX_GROUPS {
        let key = g.to_string();
        let axes = file
            .group
            .get(&key)
            .and_then(|s| s.axes.as_ref())
            .or_else(|| cx.card.group.get(&key).and_then(|s| s.axes.as_ref()));
        for &a in axes.into_iter().flatten() {
            grouped[a as usize % MAX_AXES] = Some(g);
        }
    }
    let scale_of = |a: usize| {
        let key = a.to_string();
        file.axis
            .get(&key)
            .or_else(|| cx.card.axis.get(&key))
            .map_or(1.0, |s| s.scale)
    };
    let no_axis = |a: u8| format!("no such axis {a}: the card has {n} (0 to {})", n - 1);
    for (key, g) in &file.gantry {
        let gi = index_key("gantry", key, MAX_GANTRIES)?;
        let p = format!("gantry.{gi}");
        let err = |k: &str, why: String| Err((format!("{p}.{k}"), why));
        match cx.card.gantry.get(key) {
            Some(held) if held == g => {}
            Some(held) => {
                return Err((
                    p.clone(),
                    format!(
                        "gantry {gi} is formed with other settings (master {}, slaves {:?}): \
                         dissolve it first (`mcctl gantry dissolve {gi}`)",
                        held.master, held.slaves
                    ),
                ))
            }
            None => {}
        }
        let m = g.master;
        if usize::from(m) >= n {
            return err("master", no_axis(m));
        }
        if g.slaves.is_empty() || g.slaves.len() > GANTRY_MAX_SLAVES {
            return err(
                "slaves",
                format!(
                    "{} slaves: a gantry has 1 to {GANTRY_MAX_SLAVES}",
                    g.slaves.len()
                ),
            );
        }
        for (k, &a) in g.slaves.iter().enumerate() {
            if usize::from(a) >= n {
                return err("slaves", no_axis(a));
            }
            if a == m || g.slaves[..k].contains(&a) {
                return err(
                    "slaves",
                    format!(
                        "axis {a} is the master or listed twice: {}",
                        nack_text(NackCode::GantryAxes)
                    ),
                );
            }
        }
        for (name, v, max) in [("kp", g.kp, GANTRY_KP_MAX), ("ki", g.ki, GANTRY_KI_MAX)] {
            if !v.is_finite() {
                return err(name, nack_text(NackCode::NotFinite));
            }
            if !(0.0..=max).contains(&v) {
                return err(
                    name,
                    format!(
                        "{v}: must lie in 0..={max:e}: {}",
                        nack_text(NackCode::GantryGains)
                    ),
                );
            }
        }
        let scale = scale_of(usize::from(m));
        if let Some(&a) = g
            .slaves
            .iter()
            .find(|&&a| scale_of(usize::from(a)) != scale)
        {
            return err(
                "slaves",
                format!(
                    "axis {a} has scale {}, the master (axis {m}) {scale}: a gantry's axes \
                     share the master's scale",
                    scale_of(usize::from(a))
                ),
            );
        }
        let in_range = |x: f64| x.is_finite() && (x * scale).abs() <= firmware_proto::MAX_POSITION;
        if !(in_range(g.skew_limit) && g.skew_limit > 0.0) {
            return err(
                "skew_limit",
                format!(
                    "{}: a positive length within the position range: {}",
                    g.skew_limit,
                    nack_text(NackCode::GantryGains)
                ),
            );
        }
        if !g.offsets.is_empty() && g.offsets.len() != g.slaves.len() {
            return err(
                "offsets",
                format!(
                    "{} values: one per slave ({}), or none (0 each)",
                    g.offsets.len(),
                    g.slaves.len()
                ),
            );
        }
        if let Some(o) = g.offsets.iter().find(|&&o| !in_range(o)) {
            return err(
                "offsets",
                format!(
                    "{o}: beyond the position range: {}",
                    nack_text(NackCode::GantryGains)
                ),
            );
        }
        for (k, &a) in std::iter::once(&m).chain(&g.slaves).enumerate() {
            let which = if k == 0 { "master" } else { "slaves" };
            if let Some(o) = member[usize::from(a)].filter(|&o| o != gi) {
                return err(
                    which,
                    format!(
                        "axis {a} is in gantry {o}: {}",
                        nack_text(NackCode::GantryInUse)
                    ),
                );
            }
            member[usize::from(a)] = Some(gi);
            if let (true, Some(o)) = (k > 0, grouped[usize::from(a)]) {
                return err(
                    which,
                    format!(
                        "axis {a} is in group {o}: {}",
                        nack_text(NackCode::GantryInUse)
                    ),
                );
            }
        }
        if cx.card.gantry.get(key) == Some(g) {
            continue;
        }
        let state = cx.axis_states[usize::from(m)];
        let at_rest = matches!(state, AxisState::Standstill | AxisState::Disabled);
        if let Some(&a) = std::iter::once(&m)
            .chain(&g.slaves)
            .find(|&&a| !at_rest || cx.axis_states[usize::from(a)] != state)
        {
            return err(
                "master",
                format!(
                    "the gantry's axes must be at rest, all powered or all disabled, to form it: \
                     axis {a} is {:?}, the master {state:?}: {}",
                    cx.axis_states[usize::from(a)],
                    nack_text(NackCode::GantryState)
                ),
            );
        }
    }
    Ok(())
}

/// `[card]`: the servo rate, with every axis disabled to change it. The servo rate the other
/// sections are checked at: the file's, else the card's.
fn check_card(file: &Config, cx: &Context<'_>) -> std::result::Result<u32, Refusal> {
    let card = cx.card;
    let rate = file
        .card
        .or(card.card)
        .map_or(firmware_proto::SERVO_RATE_MIN_HZ, |c| c.servo_rate_hz);
    if let Some(c) = &file.card {
        let range = firmware_proto::SERVO_RATE_MIN_HZ..=firmware_proto::SERVO_RATE_MAX_HZ;
        if !range.contains(&c.servo_rate_hz) {
            return Err((
                "card.servo_rate_hz".into(),
                format!(
                    "{} Hz: the servo rate must lie in {}..={} Hz",
                    c.servo_rate_hz,
                    range.start(),
                    range.end()
                ),
            ));
        }
        if Some(*c) != card.card && cx.axis_states.iter().any(|s| *s != AxisState::Disabled) {
            return Err((
                "card.servo_rate_hz".into(),
                nack_text(NackCode::AxesEnabled),
            ));
        }
    }
    Ok(rate)
}

/// `[safety]`: the card-wide block. The maximum stop time every axis's stop ramp must fit
/// within: the file's, else the card's.
fn check_safety(file: &Config, cx: &Context<'_>) -> std::result::Result<f64, Refusal> {
    let safety = file.safety.or(cx.card.safety).map(|s| s.block());
    if let Some(s) = &file.safety {
        let good = SafetySection {
            watchdog_timeout_us: card_firmware::host::WATCHDOG_TIMEOUT_DEFAULT_US,
            estop_input_category: 1,
            max_stop_time_us: card_firmware::host::MAX_STOP_TIME_DEFAULT_US,
        };
        let period = cx.host_period_us;
        refuse("safety", s, &good, |s| {
            SafetyConfig::validate(&s.block(), period).map(|_| ())
        })?;
    }
    Ok(safety
        .and_then(|b| SafetyConfig::validate(&b, 0).ok())
        .map_or(f64::INFINITY, |c| c.max_stop_time()))
}

/// `[io]`: one debounce per input, and the block the card would take.
fn check_io(file: &Config) -> std::result::Result<(), Refusal> {
    if let Some(io) = &file.io {
        if io.debounce.len() != INPUTS {
            return Err((
                "io.debounce".into(),
                format!("{} values: one per input ({INPUTS})", io.debounce.len()),
            ));
        }
        let good = IoSection {
            polarity: 0,
            rise_events: 0,
            fall_events: 0,
            debounce: vec![0; INPUTS],
        };
        refuse("io", io, &good, |s| {
            IoConfig::validate(&s.block()).map(|_| ())
        })?;
    }
    Ok(())
}

/// `[axis.N]`: the servo law and its table, the scale and the servo block, then the axis's
/// filter, safety and homing tables.
fn check_axis(
    key: &str,
    ax: &AxisSection,
    good: &AxisSection,
    cx: &Context<'_>,
    rate: u32,
    max_stop: f64,
) -> std::result::Result<(), Refusal> {
    let a = index_key("axis", key, cx.num_axes)?;
    let p = format!("axis.{a}");
    match (ax.servo_law, &ax.pdplus) {
        (ServoLaw::Pdplus, None) => {
            return Err((
                format!("{p}.servo_law"),
                format!("servo_law = \"pdplus\" needs the table [{p}.pdplus]"),
            ))
        }
        (ServoLaw::Ffpiv | ServoLaw::Pidff, Some(_)) => {
            return Err((
                format!("{p}.pdplus"),
                "a PD+ table on an axis whose servo_law is not \"pdplus\"".into(),
            ))
        }
        _ => {}
    }
    match (ax.servo_law, &ax.pidff) {
        (ServoLaw::Pidff, None) => {
            return Err((
                format!("{p}.servo_law"),
                format!("servo_law = \"pidff\" needs the table [{p}.pidff]"),
            ))
        }
        (ServoLaw::Ffpiv | ServoLaw::Pdplus, Some(_)) => {
            return Err((
                format!("{p}.pidff"),
                "a PID+FF table on an axis whose servo_law is not \"pidff\"".into(),
            ))
        }
        _ => {}
    }
    let mut good = good.clone();
    if ax.servo_law != ServoLaw::Pdplus {
        good.pdplus = None;
    }
    if ax.servo_law == ServoLaw::Pidff {
        good.pidff = Some(PidffSection::from(&firmware_proto::AxisPidff::default()));
    }
    good.servo_law = ax.servo_law;
    refuse(&p, ax, &good, |s| {
        if !s.scale.is_finite() {
            return Err(NackCode::NotFinite);
        }
        if !SCALE_RANGE.contains(&s.scale.abs()) {
            return Err(NackCode::OutOfRange);
        }
        let (cfg, pd, pid) = s.servo_blocks();
        validate_axis_config(&cfg, &pd, &pid).map(|_| ())
    })?;
    check_axis_filter(&p, ax, &good, rate)?;
    check_axis_safety(&p, ax, &good, rate, max_stop)?;
    check_axis_homing(&p, ax, &good, rate)?;
    for (k, b) in &ax.biquad {
        let slot = index_key(&format!("{p}.biquad"), k, crate::BIQUADS)?;
        check_biquad(&format!("{p}.biquad.{slot}"), b, rate)?;
    }
    // `modulo` (layout 1.10): the card's range in the file's scale, and a positive scale.
    if let Some(m) = ax.modulo {
        let counts = m * ax.scale;
        let bad = if !m.is_finite() || m < 0.0 {
            Some("the period must be a positive, finite length (0: linear)".to_string())
        } else if m != 0.0 && ax.scale < 0.0 {
            Some("a modulo axis needs a positive scale".to_string())
        } else if m != 0.0 && !firmware_proto::MODULO_RANGE.contains(&counts) {
            Some(nack_text(NackCode::ModuloRange))
        } else {
            None
        };
        if let Some(why) = bad {
            return Err((format!("{p}.modulo"), why));
        }
    }
    // [axis.N.compensation]: the card's checks of the table, in the file's scale.
    if let Some(c) = &ax.compensation {
        crate::Compensation::from(c)
            .nack(ax.scale, rate)
            .map_err(|code| (format!("{p}.compensation"), nack_text(code)))?;
    }
    Ok(())
}

/// `[axis.N.filter]`: the acc/dec filters at the servo rate.
fn check_axis_filter(
    p: &str,
    ax: &AxisSection,
    good: &AxisSection,
    rate: u32,
) -> std::result::Result<(), Refusal> {
    if ax.filter.is_none() {
        return Ok(());
    }
    let ts = 1.0 / rate as f64;
    refuse(p, ax, good, |s| {
        let Some(f) = &s.filter else { return Ok(()) };
        decode_axis_filter(&f.block())?.validate(ts)
    })
}

/// `[axis.N.safety]`: the axis's safety block, its stop ramp within the maximum stop time.
fn check_axis_safety(
    p: &str,
    ax: &AxisSection,
    good: &AxisSection,
    rate: u32,
    max_stop: f64,
) -> std::result::Result<(), Refusal> {
    if ax.safety.is_none() {
        return Ok(());
    }
    refuse(p, ax, good, |s| {
        let Some(f) = &s.safety else { return Ok(()) };
        AxisSafetyConfig::from_block(&f.block())?.validate_on_card(rate, max_stop)
    })
}

/// `[axis.N.homing]`: the homing method and its settings.
fn check_axis_homing(
    p: &str,
    ax: &AxisSection,
    good: &AxisSection,
    rate: u32,
) -> std::result::Result<(), Refusal> {
    if ax.homing.is_none() {
        return Ok(());
    }
    refuse(p, ax, good, |s| {
        let Some(h) = &s.homing else { return Ok(()) };
        HomingConfig::validate(&h.block(), rate).map(|_| ())
    })
}

/// With a `[safety]` section: the stop ramps of the axes the file leaves as they are must fit
/// its maximum stop time too.
fn check_stop_ramps(
    file: &Config,
    cx: &Context<'_>,
    max_stop: f64,
) -> std::result::Result<(), Refusal> {
    if file.safety.is_none() {
        return Ok(());
    }
    for (key, ax) in &cx.card.axis {
        let from_file = file.axis.get(key).and_then(|a| a.safety);
        if let Some(s) = from_file.or(ax.safety) {
            let c = AxisSafetyConfig::from_block(&s.block());
            if c.is_ok_and(|c| c.stop_time_from(c.max_velocity) > max_stop) {
                return Err((
                    "safety.max_stop_time_us".into(),
                    format!(
                        "axis {key}'s stop ramp from its max_velocity does not fit: {}",
                        nack_text(NackCode::StopTooLong)
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// `[group.N]` and `[group.N.path]`: each configuration, its axes in no other group, the group
/// disabled to change it; then its path settings.
fn check_groups(file: &Config, cx: &Context<'_>, rate: u32) -> std::result::Result<(), Refusal> {
    // Which group each axis is in, after the file: the card's groups the file leaves as they
    // are, then the file's in turn.
    let mut owner = [None::<usize>; MAX_AXES];
    for (key, g) in &cx.card.group {
        if file.group.get(key).is_some_and(|f| f.axes.is_some()) {
            continue;
        }
        for &a in g.axes.iter().flatten() {
            owner[a as usize % MAX_AXES] = key.parse().ok();
        }
    }
    for (key, g) in &file.group {
        let gi = index_key("group", key, MAX_GROUPS)?;
        let p = format!("group.{gi}");
        let naxes = check_group(&p, gi, key, g, cx, &mut owner)?;
        if let Some(path) = &g.path {
            check_group_path(&p, path, naxes, rate)?;
        }
    }
    Ok(())
}

/// `[group.N]` (prefix `p`): all four parts or none; the block the card would take, its axes
/// in no other group (`owner`, updated), the group disabled to change it. The number of group
/// axes its path is checked for.
fn check_group(
    p: &str,
    gi: usize,
    key: &str,
    g: &GroupSection,
    cx: &Context<'_>,
    owner: &mut [Option<usize>; MAX_AXES],
) -> std::result::Result<usize, Refusal> {
    let card = cx.card;
    let parts = [
        g.axes.is_some(),
        g.accdec.is_some(),
        g.interpolator.is_some(),
        g.tolerance.is_some(),
    ];
    if parts.iter().any(|&x| x) && !parts.iter().all(|&x| x) {
        let missing = ["axes", "accdec", "interpolator", "tolerance"]
            .iter()
            .zip(parts)
            .find(|(_, x)| !x)
            .map_or("axes", |(n, _)| n);
        return Err((
            format!("{p}.{missing}"),
            "a group's configuration needs all of axes, accdec, interpolator and tolerance".into(),
        ));
    }
    let mut naxes = MAX_AXES;
    if let Some(block) = g.config_block() {
        let good = GroupSection {
            axes: g.axes.clone(),
            accdec: Some(AccDecName::Pre),
            interpolator: Some(InterpolatorName::Exact),
            tolerance: Some(1.0),
            home_order: None,
            path: None,
        };
        let n = cx.num_axes;
        let bad = GroupSection {
            path: None,
            ..g.clone()
        };
        if let Err(code) = validate_group_config(&block, n) {
            let key = match code {
                // Layout 1.11: the home order's own refusals, and more stages than it holds.
                NackCode::HomeAxis | NackCode::HomeTwice | NackCode::HomeStage => {
                    format!("{p}.home_order")
                }
                NackCode::BadConfig
                    if g.home_order
                        .as_ref()
                        .is_some_and(|o| o.len() > firmware_proto::cmd::GROUP_HOME_STAGES) =>
                {
                    format!("{p}.home_order")
                }
                NackCode::BadAxis | NackCode::BadConfig
                    if block.naxes == 0
                        || block.naxes as usize > MAX_AXES
                        || g.axes.iter().flatten().any(|&a| a as usize >= n) =>
                {
                    format!("{p}.axes")
                }
                _ => match blame(&bad, &good, |s| {
                    s.config_block()
                        .map_or(Ok(()), |b| validate_group_config(&b, n).map(|_| ()))
                }) {
                    Some(k) => format!("{p}.{k}"),
                    None => format!("{p}.axes"),
                },
            };
            return Err((key, nack_text(code)));
        }
        naxes = block.naxes as usize;
        for &a in g.axes.iter().flatten() {
            if let Some(o) = owner[a as usize].filter(|&o| o != gi) {
                return Err((
                    format!("{p}.axes"),
                    format!(
                        "axis {a} is in group {o}: {}",
                        nack_text(NackCode::AxisInOtherGroup)
                    ),
                ));
            }
            owner[a as usize] = Some(gi);
        }
        let held = card.group.get(key).and_then(|c| c.config_block());
        if held != Some(block) && cx.group_states.get(gi) != Some(&GroupState::Disabled) {
            return Err((
                format!("{p}.axes"),
                format!(
                    "the group must be disabled to configure it: {}",
                    nack_text(NackCode::InvalidState)
                ),
            ));
        }
    } else if let Some(c) = card.group.get(key).and_then(|c| c.axes.as_ref()) {
        naxes = c.len();
    }
    Ok(naxes)
}

/// `[group.N.path]` (prefix `p`): one limit per axis slot, and the block the card would take
/// for a group of `naxes` axes.
fn check_group_path(
    p: &str,
    path: &PathSection,
    naxes: usize,
    rate: u32,
) -> std::result::Result<(), Refusal> {
    for (name, v) in [
        ("vmax", &path.vmax),
        ("amax", &path.amax),
        ("jmax", &path.jmax),
    ] {
        if v.len() != MAX_AXES {
            return Err((
                format!("{p}.path.{name}"),
                format!("{} values: one per group axis slot ({MAX_AXES})", v.len()),
            ));
        }
    }
    let good = PathSection::from(&firmware_proto::GroupPath::default());
    refuse(&format!("{p}.path"), path, &good, |s| {
        validate_path_config(&s.block(), naxes, rate)
    })
}

// ----- the card --------------------------------------------------------------------------

/// What [`Card::load_config`] did.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LoadReport {
    /// The sections applied (those that differed from the card), in order.
    pub applied: Vec<String>,
}

impl Card {
    /// Every setting the card holds, read back from the card (layout 1.8).
    pub fn read_config(&self) -> Result<Config> {
        let mut cfg = Config {
            card: Some(CardSection {
                servo_rate_hz: self.servo_rate()?,
            }),
            ..Default::default()
        };
        let s = self.read_block(layout::SAFETY_CONFIG, ConfigKind::Safety, 0)?;
        cfg.safety = Some(SafetySection {
            watchdog_timeout_us: s.watchdog_timeout_us,
            estop_input_category: s.estop_input_category,
            max_stop_time_us: s.max_stop_time_us,
        });
        let io = self.read_block(layout::IO_CONFIG, ConfigKind::Io, 0)?;
        cfg.io = Some(IoSection {
            polarity: io.polarity,
            rise_events: io.rise_events,
            fall_events: io.fall_events,
            debounce: io.debounce.to_vec(),
        });
        for a in 0..self.info().axes {
            let (c, pd, pid) = self.read_axis_config(a)?;
            let f = self.read_block(layout::AXIS_FILTER.at(a), ConfigKind::AxisFilter, a)?;
            let s = self.read_block(layout::AXIS_SAFETY.at(a), ConfigKind::AxisSafety, a)?;
            let h = self.read_block(layout::AXIS_HOMING.at(a), ConfigKind::AxisHoming, a)?;
            let mut ax = AxisSection::from_blocks(&c, &pd, &pid, &f, &s, &h);
            ax.compensation = self
                .axis(a)?
                .compensation()?
                .map(|c| CompensationSection::from(&c));
            for (k, f) in self.axis(a)?.servo_filters()?.iter().enumerate() {
                let spec = f.as_ref().map(|f| f.spec);
                ax.biquad
                    .insert(k.to_string(), BiquadSection::from_spec(spec.as_ref()));
            }
            cfg.axis.insert(a.to_string(), ax);
        }
        for g in 0..MAX_GROUPS {
            let c = self.read_block(layout::GROUP_CONFIG.at(g), ConfigKind::Group, g)?;
            let p = self.read_block(layout::GROUP_PATH.at(g), ConfigKind::GroupPath, g)?;
            cfg.group
                .insert(g.to_string(), GroupSection::from_blocks(&c, &p));
        }
        for g in 0..firmware_proto::cmd::MAX_GANTRIES {
            let b = layout::GANTRY_STATUS.at(g).read(self.window());
            if let Some(s) = GantrySection::from_block(&b, self.scale(b.master as usize)) {
                cfg.gantry.insert(g.to_string(), s);
            }
        }
        for i in 0..firmware_proto::ANALOG_INPUTS {
            let a = self.analog_input(i)?;
            cfg.analog_input
                .insert(i.to_string(), AnalogInputSection::from(&a.settings));
        }
        cfg.pso = Some(PsoSection::from_status(&self.pso_status()?));
        Ok(cfg)
    }

    /// The configuration file of what the card holds (read back from the card).
    pub fn save_config(&self) -> Result<String> {
        Ok(self.read_config()?.to_toml())
    }

    /// Check the whole file against this card (nothing is applied when any value is wrong:
    /// [`Error::ConfigFile`] names the key and its line), then apply the sections that differ
    /// from what the card holds, read the card back and compare. `origin` names the text in
    /// errors (a file name). A section the card refuses after the checks passed (its state
    /// changed meanwhile) is [`Error::ConfigApply`], which says what was applied before it.
    pub fn load_config(&self, text: &str, origin: &str) -> Result<LoadReport> {
        let file = Config::parse(text, origin)?;
        let held = self.check_config(&file, text, origin)?;
        let mut report = LoadReport::default();
        self.apply_config(&file, &held, &mut report)
            .map_err(|(key, e)| Error::ConfigApply {
                key,
                applied: if report.applied.is_empty() {
                    "none".into()
                } else {
                    report.applied.join(", ")
                },
                source: Box::new(e),
            })?;
        // The card now holds what the file says.
        let now = self.read_config()?;
        if let Some(d) = differences(&file, &now).into_iter().next() {
            return Err(Error::Protocol(format!(
                "{origin}: {} reads back as {} after the load, not {}",
                d.key,
                d.card.as_deref().unwrap_or("nothing"),
                d.file
            )));
        }
        Ok(report)
    }

    /// The keys where the file and the card differ, in key order (the file is checked first,
    /// as by [`Card::load_config`], but nothing is applied).
    pub fn diff_config(&self, text: &str, origin: &str) -> Result<Vec<ConfigDifference>> {
        let file = Config::parse(text, origin)?;
        let held = self.check_config(&file, text, origin)?;
        Ok(differences(&file, &held))
    }

    /// [`Card::save_config`] into the file `path` (created or replaced).
    pub fn save_config_file(&self, path: impl AsRef<std::path::Path>) -> Result<()> {
        let path = path.as_ref();
        let text = self.save_config()?;
        std::fs::write(path, text)
            .map_err(|e| Error::io(format!("{}: cannot write", path.display()), e))
    }

    /// [`Card::load_config`] of the file `path`.
    pub fn load_config_file(&self, path: impl AsRef<std::path::Path>) -> Result<LoadReport> {
        let path = path.as_ref();
        self.load_config(&read_file(path)?, &path.display().to_string())
    }

    /// [`Card::diff_config`] of the file `path`.
    pub fn diff_config_file(
        &self,
        path: impl AsRef<std::path::Path>,
    ) -> Result<Vec<ConfigDifference>> {
        let path = path.as_ref();
        self.diff_config(&read_file(path)?, &path.display().to_string())
    }

    /// The checks of [`Card::load_config`]: the card's configuration, or the error.
    fn check_config(&self, file: &Config, text: &str, origin: &str) -> Result<Config> {
        let held = self.read_config()?;
        let axis_states = self
            .axes()
            .iter()
            .map(|a| a.status().map(|s| s.state))
            .collect::<Result<Vec<_>>>()?;
        let group_states = (0..MAX_GROUPS)
            .map(|g| self.group(g)?.status().map(|s| s.0))
            .collect::<Result<Vec<_>>>()?;
        let cx = Context {
            num_axes: self.info().axes,
            host_period_us: self.window().read32(layout::HOST_PERIOD_US),
            card: &held,
            axis_states,
            group_states,
        };
        check(file, &cx).map_err(|(key, message)| {
            let line = line_of_key(text, &key);
            file_error(origin, key, line, message)
        })?;
        Ok(held)
    }

    /// Apply the sections of `file` that differ from `held`; on a refusal, the section.
    fn apply_config(
        &self,
        file: &Config,
        held: &Config,
        report: &mut LoadReport,
    ) -> std::result::Result<(), (String, Error)> {
        let mut done = |key: String| report.applied.push(key);
        if let Some(c) = file.card.filter(|c| Some(*c) != held.card) {
            // A filter the file replaces that would not run at the new rate is emptied first
            // (every axis is disabled); the file's is set after the rate.
            for (key, ax) in &file.axis {
                let a: usize = key.parse().expect("checked");
                for k in ax.biquad.keys() {
                    let was = held.axis.get(key).and_then(|w| w.biquad.get(k));
                    let fails = was.and_then(|w| w.spec()).is_some_and(|spec| {
                        design_biquad(&spec, f64::from(c.servo_rate_hz)).is_err()
                    });
                    if fails && was != ax.biquad.get(k) {
                        let slot: usize = k.parse().expect("checked");
                        self.axis(a)
                            .and_then(|x| x.clear_servo_filter(slot))
                            .map_err(|e| (format!("axis.{a}.biquad.{k}"), e))?;
                        done(format!("axis.{a}.biquad.{k}"));
                    }
                }
            }
            self.set_servo_rate(c.servo_rate_hz)
                .map_err(|e| ("card".to_string(), e))?;
            done("card".into());
        }
        // A longer maximum stop time first, a shorter one after the axes' stop ramps.
        let safety = file.safety.filter(|s| Some(*s) != held.safety);
        let shorter = safety.is_some_and(|s| {
            held.safety
                .is_some_and(|h| s.max_stop_time_us < h.max_stop_time_us)
        });
        let apply_safety = |done: &mut dyn FnMut(String)| {
            if let Some(s) = safety {
                let b = s.block();
                self.apply_block(
                    layout::SAFETY_CONFIG,
                    |x| *x = b,
                    firmware_proto::cmd::CardCmd::ApplySafetyConfig.command(0),
                    "load configuration",
                    crate::Target::Card,
                )
                .map_err(|e| ("safety".to_string(), e))?;
                done("safety".into());
            }
            Ok(())
        };
        if !shorter {
            apply_safety(&mut done)?;
        }
        if let Some(io) = file.io.as_ref().filter(|io| Some(*io) != held.io.as_ref()) {
            self.configure_io(&io.block())
                .map_err(|e| ("io".to_string(), e))?;
            done("io".into());
        }
        for (key, ax) in &file.axis {
            let a: usize = key.parse().expect("checked");
            let was = held.axis.get(key);
            let axis = self.axis(a).map_err(|e| (format!("axis.{a}"), e))?;
            let (cfg, pd, pid) = ax.servo_blocks();
            let was_scale = was.map(|w| w.scale);
            let servo = |s: &AxisSection| {
                let (c, p, q) = s.servo_blocks();
                (AxisConfig { scale: 0.0, ..c }, p, q)
            };
            if was.map(servo) != Some(servo(ax)) {
                let apply = firmware_proto::cmd::CardCmd::ApplyAxisConfig.command(a as u16);
                let _g = self.config_lock();
                let w = self.window();
                let saved = (
                    layout::AXIS_CONFIG.at(a).read(w),
                    layout::AXIS_PDPLUS.at(a).read(w),
                    layout::AXIS_PIDFF.at(a).read(w),
                );
                self.write_block(layout::AXIS_PDPLUS.at(a), &pd);
                self.write_block(layout::AXIS_PIDFF.at(a), &pid);
                self.write_block(layout::AXIS_CONFIG.at(a), &cfg);
                let r = self.execute(apply, "load configuration", crate::Target::Axis(a));
                if r.is_err() {
                    self.write_block(layout::AXIS_CONFIG.at(a), &saved.0);
                    self.write_block(layout::AXIS_PDPLUS.at(a), &saved.1);
                    self.write_block(layout::AXIS_PIDFF.at(a), &saved.2);
                }
                r.map_err(|e| (format!("axis.{a}"), e))?;
                done(format!("axis.{a}"));
            }
            if was_scale != Some(ax.scale) {
                axis.set_scale(ax.scale)
                    .map_err(|e| (format!("axis.{a}.scale"), e))?;
                done(format!("axis.{a}.scale"));
            }
            if let Some(m) = ax.modulo {
                let held = was.and_then(|w| w.modulo).unwrap_or(0.0);
                // Read back through the card's 1/65536 count: a difference below that is none.
                if (held - m).abs() * ax.scale.abs() > 1.0 / 65_536.0 {
                    if m == 0.0 {
                        axis.clear_modulo()
                    } else {
                        axis.set_modulo(m)
                    }
                    .map_err(|e| (format!("axis.{a}.modulo"), e))?;
                    done(format!("axis.{a}.modulo"));
                }
            }
            if let Some(c) = &ax.compensation {
                if was.and_then(|w| w.compensation.as_ref()) != Some(c) {
                    axis.set_compensation(&crate::Compensation::from(c))
                        .map_err(|e| (format!("axis.{a}.compensation"), e))?;
                    done(format!("axis.{a}.compensation"));
                }
            }
            for (k, b) in &ax.biquad {
                if was.and_then(|w| w.biquad.get(k)) == Some(b) {
                    continue;
                }
                let slot: usize = k.parse().expect("checked");
                match b.spec() {
                    Some(spec) => axis.set_servo_filter(slot, &spec),
                    None => axis.clear_servo_filter(slot),
                }
                .map_err(|e| (format!("axis.{a}.biquad.{k}"), e))?;
                done(format!("axis.{a}.biquad.{k}"));
            }
            let subs: [(&str, bool, ConfigKind); 3] = [
                (
                    "filter",
                    ax.filter.is_some() && ax.filter != was.and_then(|w| w.filter),
                    ConfigKind::AxisFilter,
                ),
                (
                    "safety",
                    ax.safety.is_some() && ax.safety != was.and_then(|w| w.safety),
                    ConfigKind::AxisSafety,
                ),
                (
                    "homing",
                    ax.homing.is_some() && ax.homing != was.and_then(|w| w.homing),
                    ConfigKind::AxisHoming,
                ),
            ];
            for (name, differs, kind) in subs {
                if !differs {
                    continue;
                }
                let cmd = |c: firmware_proto::cmd::CardCmd| c.command(a as u16);
                let t = crate::Target::Axis(a);
                let what = "load configuration";
                let r = match kind {
                    ConfigKind::AxisFilter => {
                        let b = ax.filter.expect("differs").block();
                        self.apply_block(
                            layout::AXIS_FILTER.at(a),
                            |x| *x = b,
                            cmd(firmware_proto::cmd::CardCmd::ApplyAxisFilter),
                            what,
                            t,
                        )
                    }
                    ConfigKind::AxisSafety => {
                        let b = ax.safety.expect("differs").block();
                        self.apply_block(
                            layout::AXIS_SAFETY.at(a),
                            |x| *x = b,
                            cmd(firmware_proto::cmd::CardCmd::ApplyAxisSafety),
                            what,
                            t,
                        )
                    }
                    _ => {
                        let b = ax.homing.expect("differs").block();
                        self.apply_block(
                            layout::AXIS_HOMING.at(a),
                            |x| *x = b,
                            cmd(firmware_proto::cmd::CardCmd::ApplyAxisHoming),
                            what,
                            t,
                        )
                    }
                };
                r.map_err(|e| (format!("axis.{a}.{name}"), e))?;
                done(format!("axis.{a}.{name}"));
            }
        }
        if shorter {
            apply_safety(&mut done)?;
        }
        for (key, g) in &file.group {
            let gi: usize = key.parse().expect("checked");
            let was = held.group.get(key);
            let t = crate::Target::Group(gi);
            if let Some(b) = g.config_block() {
                if was.and_then(|w| w.config_block()) != Some(b) {
                    self.apply_block(
                        layout::GROUP_CONFIG.at(gi),
                        |x| *x = b,
                        firmware_proto::cmd::GroupCmd::Configure.command(gi as u16),
                        "load configuration",
                        t,
                    )
                    .map_err(|e| (format!("group.{gi}"), e))?;
                    let mut axes = [0usize; MAX_AXES];
                    for (d, &a) in axes.iter_mut().zip(g.axes.iter().flatten()) {
                        *d = a as usize;
                    }
                    crate::card::lock(&self.inner().group_axes)[gi] =
                        Some((b.naxes as usize, axes));
                    done(format!("group.{gi}"));
                }
            }
            if let Some(p) = g
                .path
                .as_ref()
                .filter(|p| Some(*p) != was.and_then(|w| w.path.as_ref()))
            {
                let b = p.block();
                self.apply_block(
                    layout::GROUP_PATH.at(gi),
                    |x| *x = b,
                    firmware_proto::cmd::GroupCmd::ApplyPath.command(gi as u16),
                    "load configuration",
                    t,
                )
                .map_err(|e| (format!("group.{gi}.path"), e))?;
                done(format!("group.{gi}.path"));
            }
        }
        for (key, a) in &file.analog_input {
            if held.analog_input.get(key) == Some(a) {
                continue;
            }
            let i: usize = key.parse().expect("checked");
            self.configure_analog_input(i, &a.settings())
                .map_err(|e| (format!("analog_input.{i}"), e))?;
            done(format!("analog_input.{i}"));
        }
        // The PSO after the groups: it runs on one.
        if let Some(p) = file.pso.as_ref().filter(|p| held.pso.as_ref() != Some(*p)) {
            match p.settings() {
                Some((g, s)) => self.pso_counts(g, &s),
                None => self.pso_off(),
            }
            .map_err(|e| ("pso".to_string(), e))?;
            done("pso".into());
        }
        // Gantries last: their members' scales and settings are the file's by now.
        for (key, g) in &file.gantry {
            if held.gantry.get(key) == Some(g) {
                continue;
            }
            let gi: usize = key.parse().expect("checked");
            let slaves: Vec<usize> = g.slaves.iter().map(|&a| usize::from(a)).collect();
            self.gantry_at(gi, usize::from(g.master), &slaves, &g.config())
                .map_err(|e| (format!("gantry.{gi}"), e))?;
            done(format!("gantry.{gi}"));
        }
        Ok(())
    }
}

/// The keys of `file` whose values differ from `card`'s, in key order (an array is one key).
pub fn differences(file: &Config, card: &Config) -> Vec<ConfigDifference> {
    // A modulo period is held in 1/65536 count: the file's as the card would hold it.
    let mut file = file.clone();
    for ax in file.axis.values_mut() {
        if let Some(m) = ax.modulo.as_mut() {
            let counts = *m * ax.scale;
            if counts.is_finite() && counts > 0.0 && ax.scale > 0.0 {
                let held = firmware_proto::modulo_subcounts(counts) as f64 / 65536.0;
                *m = user_modulo(held, ax.scale);
            }
        }
    }
    let (Ok(f), Ok(c)) = (toml::Value::try_from(&file), toml::Value::try_from(card)) else {
        return Vec::new();
    };
    let mut leaves = Vec::new();
    collect_leaves(&f, &mut Vec::new(), &mut leaves);
    let mut out = Vec::new();
    // Arrays compare whole (one line for `debounce`, `vmax`…).
    let mut seen = std::collections::BTreeSet::new();
    for path in leaves {
        let path = match path.last().map(|p| p.parse::<usize>().is_ok()) {
            Some(true) => path[..path.len() - 1].to_vec(),
            _ => path,
        };
        if !seen.insert(path.clone()) {
            continue;
        }
        let fv = get_path(&f, &path).expect("a leaf of the file");
        let cv = get_path(&c, &path);
        if cv != Some(fv) {
            out.push(ConfigDifference {
                key: path.join("."),
                file: fv.to_string(),
                card: cv.map(|v| v.to_string()),
            });
        }
    }
    out
}
