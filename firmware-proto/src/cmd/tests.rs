//! Every command's encode → decode round trip (proptest over its fields' ranges), and the
//! decode error of each malformed field.

use super::*;
use crate::motion_sync::{MasterSource, AUX_ENCODERS, CAM_MAX_POINTS, CAM_TABLES, PVT_LAST};
use crate::wire::{ConfigKind, StopCategory};
use crate::{raw, COMPARE_CHANNELS, MAX_AXES, NURBS_DATA_MAX, PROBE_CHANNELS, PTP_LIMITS_MAX};
use proptest::prelude::*;
use proptest::strategy::{BoxedStrategy, Union};

/// Any `f64` but NaN (which is not equal to itself): normal, subnormal, ±0, ±inf, huge.
fn num() -> BoxedStrategy<f64> {
    prop_oneof![
        any::<u64>().prop_map(f64::from_bits),
        Just(0.0),
        Just(-0.0),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        -1e7..1e7f64,
    ]
    .prop_filter("NaN is not equal to itself", |x| !x.is_nan())
    .boxed()
}

fn nums<const N: usize>() -> BoxedStrategy<[f64; N]> {
    proptest::collection::vec(num(), N)
        .prop_map(|v| core::array::from_fn(|i| v[i]))
        .boxed()
}

fn vec_of<T: core::fmt::Debug + Clone + 'static, const N: usize>(
    s: BoxedStrategy<T>,
    min: usize,
) -> BoxedStrategy<heapless::Vec<T, N>> {
    proptest::collection::vec(s, min..=N)
        .prop_map(|v| heapless::Vec::from_slice(&v).unwrap())
        .boxed()
}

fn feed_limits() -> BoxedStrategy<FeedLimits> {
    nums::<4>().prop_map(FeedLimits::from_array).boxed()
}

fn move_opts() -> BoxedStrategy<MoveOpts> {
    (any::<bool>(), any::<bool>(), 0u8..4)
        .prop_map(|(relative, buffered, feed_type)| MoveOpts {
            relative,
            buffered,
            feed_type,
        })
        .boxed()
}

fn arc() -> BoxedStrategy<ArcGeometry> {
    (
        nums::<2>(),
        nums::<2>(),
        nums::<{ MAX_AXES - 2 }>(),
        0u8..4,
        0u8..4,
        any::<(bool, bool)>(),
        (0u8..8, 0u8..8),
    )
        .prop_map(
            |(end, aux, helix, mode, plane, (ccw, helix_relative), axes)| ArcGeometry {
                end,
                aux,
                helix,
                flags: ArcFlags {
                    mode,
                    plane,
                    axes,
                    ccw,
                    helix_relative,
                },
            },
        )
        .boxed()
}

fn path_flags() -> BoxedStrategy<PathFlags> {
    (any::<bool>(), 0u8..8, 0u8..4, any::<bool>())
        .prop_map(|(relative, buffer, transition, last)| PathFlags {
            relative,
            buffer,
            transition,
            last,
        })
        .boxed()
}

fn size() -> BoxedStrategy<CurveSize> {
    nums::<3>().prop_map(CurveSize::from_array).boxed()
}

fn master() -> BoxedStrategy<Master> {
    prop_oneof![
        (0..MAX_AXES as u8).prop_map(|index| Master {
            source: MasterSource::Commanded,
            index
        }),
        (0..MAX_AXES as u8).prop_map(|index| Master {
            source: MasterSource::Actual,
            index
        }),
        (0..MAX_AXES as u8).prop_map(|index| Master {
            source: MasterSource::ActualLead,
            index
        }),
        (0..AUX_ENCODERS as u8).prop_map(|index| Master {
            source: MasterSource::Aux,
            index
        }),
    ]
    .boxed()
}

fn sync_limits() -> BoxedStrategy<SyncLimits> {
    nums::<3>()
        .prop_map(|[vmax, amax, jerk]| SyncLimits { vmax, amax, jerk })
        .boxed()
}

/// `f64`s finite (for the commands whose every argument must be).
fn finite() -> BoxedStrategy<f64> {
    num().prop_filter("finite", |x| x.is_finite()).boxed()
}

fn gear_in() -> BoxedStrategy<GearIn> {
    (master(), finite(), finite(), finite(), finite(), finite())
        .prop_map(
            |(master, numerator, denominator, vmax, amax, jerk)| GearIn {
                master,
                numerator,
                denominator,
                limits: SyncLimits { vmax, amax, jerk },
            },
        )
        .boxed()
}

fn axis_cmd() -> BoxedStrategy<AxisCmd> {
    let kind = prop_oneof![
        Just(MoveKind::Absolute),
        Just(MoveKind::Relative),
        Just(MoveKind::Additive)
    ];
    let ramp = || {
        nums::<2>()
            .prop_map(|[dmax, jerk]| StopRamp { dmax, jerk })
            .boxed()
    };
    Union::new(vec![
        Just(AxisCmd::PowerOn).boxed(),
        Just(AxisCmd::PowerOff).boxed(),
        (kind, num(), nums::<7>(), any::<bool>(), 0..4u32)
            .prop_map(|(k, position, l, buffered, dir)| {
                AxisCmd::Move(
                    k,
                    PositionMove {
                        position,
                        limits: MoveLimits::from_array(l),
                        buffered,
                        direction: MoveDirection::ALL[dir as usize],
                    },
                )
            })
            .boxed(),
        nums::<4>()
            .prop_map(|[velocity, amax, dmax, jerk]| {
                AxisCmd::MoveVelocity(VelocityMove {
                    velocity,
                    amax,
                    dmax,
                    jerk,
                })
            })
            .boxed(),
        num()
            .prop_map(|velocity| AxisCmd::Jog(Jog { velocity }))
            .boxed(),
        num()
            .prop_map(|factor| AxisCmd::SetOverride(Override { factor }))
            .boxed(),
        ramp().prop_map(AxisCmd::Halt).boxed(),
        ramp().prop_map(AxisCmd::Stop).boxed(),
        Just(AxisCmd::StopRelease).boxed(),
        Just(AxisCmd::Reset).boxed(),
        num()
            .prop_map(|position| AxisCmd::Home(Home { position }))
            .boxed(),
        (num(), any::<bool>())
            .prop_map(|(position, relative)| {
                AxisCmd::SetPosition(SetPosition { position, relative })
            })
            .boxed(),
        // Layout 1.9: compensation.
        (0..=COMP_MAX_POINTS as u16, nums::<4>(), any::<bool>())
            .prop_map(|(points, [bound, backlash, ramp_vel, ramp_acc], bidir)| {
                AxisCmd::CompTable(CompHeader {
                    points,
                    bound,
                    backlash,
                    ramp_vel,
                    ramp_acc,
                    bidir,
                })
            })
            .boxed(),
        (
            0..COMP_MAX_POINTS as u16,
            proptest::collection::vec(nums::<3>(), 1..=COMP_DATA_MAX),
        )
            .prop_map(|(first, pts)| {
                let pts: Vec<CompPointArgs> = pts
                    .into_iter()
                    .map(|[position, forward, reverse]| CompPointArgs {
                        position,
                        forward,
                        reverse,
                    })
                    .collect();
                AxisCmd::CompData(CompData::new(first, &pts))
            })
            .boxed(),
        (0..=COMP_MAX_POINTS as u16)
            .prop_map(|first| AxisCmd::CompRead(CompRead { first }))
            .boxed(),
        // Layout 1.10: the handwheel.
        (
            0..AUX_ENCODERS as u8,
            1..=10_000i32,
            any::<bool>(),
            1..=1024u16,
        )
            .prop_map(|(input, r, neg, detent)| {
                let ratio = if neg { -r } else { r };
                AxisCmd::Handwheel(Handwheel {
                    input,
                    ratio,
                    detent,
                })
            })
            .boxed(),
        Just(AxisCmd::HandwheelOff).boxed(),
        num()
            .prop_map(|modulo| AxisCmd::SetModulo(SetModulo { modulo }))
            .boxed(),
        (
            0..BIQUADS as u8,
            0..4usize,
            [num(), num(), num(), num()],
            [num(), num(), num(), num(), num()],
        )
            .prop_map(|(slot, k, [f, d, depth, f2], coeffs)| {
                AxisCmd::ServoFilterSet(ServoFilterSet {
                    slot,
                    spec: BiquadSpec {
                        kind: BiquadKind::ALL[k],
                        freq_hz: f,
                        damping: d,
                        depth_db: depth,
                        freq2_hz: f2,
                        coeffs,
                    },
                })
            })
            .boxed(),
        (0..BIQUADS as u8)
            .prop_map(|slot| AxisCmd::ServoFilterClear(ServoFilterClear { slot }))
            .boxed(),
    ])
    .boxed()
}

/// A filter's slot and kind are integers in range: else `MC_NACK_FILTER_KIND` (NaN:
/// `MC_NACK_NOT_FINITE`); the numbers after them are the card's to check.
#[test]
fn filter_commands_refuse_slots_and_kinds_out_of_range() {
    let set = |slot: f64, kind: f64| {
        let mut args = [f64::NAN; CMD_ARGS];
        args[0] = slot;
        args[1] = kind;
        ServoFilterSet::decode(0, &args).map_err(|e| e.nack)
    };
    assert!(set(3.0, 4.0).is_ok());
    assert_eq!(set(4.0, 1.0), Err(NackCode::FilterKind));
    assert_eq!(set(0.5, 1.0), Err(NackCode::FilterKind));
    assert_eq!(set(0.0, 0.0), Err(NackCode::FilterKind));
    assert_eq!(set(0.0, 5.0), Err(NackCode::FilterKind));
    assert_eq!(set(f64::NAN, 1.0), Err(NackCode::NotFinite));
    let mut args = [0.0; CMD_ARGS];
    args[0] = 4.0;
    assert_eq!(
        ServoFilterClear::decode(0, &args).map_err(|e| e.nack),
        Err(NackCode::FilterKind)
    );
}

#[test]
fn compensation_commands_refuse_counts_and_flags_out_of_range() {
    let mut args = [0.0; CMD_ARGS];
    args[0] = 257.0;
    let e = CompHeader::decode(0, &args).unwrap_err();
    assert_eq!(e.nack, NackCode::CompTable);
    args[0] = 3.0;
    assert_eq!(
        CompHeader::decode(2, &args).unwrap_err().nack,
        NackCode::CompTable
    );
    args[0] = f64::NAN;
    assert_eq!(
        CompHeader::decode(0, &args).unwrap_err().nack,
        NackCode::NotFinite
    );
    let mut args = [0.0; CMD_ARGS];
    args[1] = 5.0;
    assert_eq!(
        CompData::decode(0, &args).unwrap_err().nack,
        NackCode::CompSequence
    );
    args[1] = 0.0;
    assert_eq!(
        CompData::decode(0, &args).unwrap_err().nack,
        NackCode::CompSequence
    );
    args[1] = 4.0;
    args[0] = 256.0;
    assert_eq!(
        CompData::decode(0, &args).unwrap_err().nack,
        NackCode::CompSequence
    );
    args[0] = 252.0;
    assert_eq!(CompData::decode(0, &args).unwrap().points().len(), 4);
}

fn group_cmd() -> BoxedStrategy<GroupCmd> {
    let ramp = || {
        nums::<2>()
            .prop_map(|[dmax, jerk]| StopRamp { dmax, jerk })
            .boxed()
    };
    let line = || {
        (feed_limits(), nums::<MAX_AXES>(), move_opts())
            .prop_map(|(limits, targets, opts)| LinearMove {
                limits,
                targets,
                opts,
            })
            .boxed()
    };
    Union::new(vec![
        Just(GroupCmd::Configure).boxed(),
        Just(GroupCmd::Enable).boxed(),
        Just(GroupCmd::Disable).boxed(),
        ramp().prop_map(GroupCmd::Stop).boxed(),
        Just(GroupCmd::StopRelease).boxed(),
        Just(GroupCmd::Reset).boxed(),
        ramp().prop_map(GroupCmd::Halt).boxed(),
        line().prop_map(GroupCmd::MoveLinear).boxed(),
        (feed_limits(), arc(), move_opts())
            .prop_map(|(limits, arc, opts)| {
                GroupCmd::MoveCircular(CircularMove { limits, arc, opts })
            })
            .boxed(),
        (line(), any::<bool>())
            .prop_map(|(line, axis_limits)| GroupCmd::MovePtp(PtpMove { line, axis_limits }))
            .boxed(),
        (
            0..=1_000_000_000u32,
            vec_of::<_, PTP_LIMITS_MAX>(feed_limits(), 1),
        )
            .prop_map(|(first, limits)| GroupCmd::PtpLimits(PtpLimits { first, limits }))
            .boxed(),
        nums::<2>()
            .prop_map(|[feed, rapid]| GroupCmd::SetOverride(GroupOverride { feed, rapid }))
            .boxed(),
        (size(), nums::<5>(), any::<(bool, bool)>(), 0u8..4)
            .prop_map(
                |(size, [feed, accel, jerk, chord_tolerance, budget], (b, s), ft)| {
                    GroupCmd::NurbsBegin(NurbsBegin {
                        size,
                        feed,
                        accel,
                        jerk,
                        chord_tolerance,
                        budget,
                        buffered: b,
                        saturation: s,
                        feed_type: ft,
                    })
                },
            )
            .boxed(),
        (0..=1_000_000_000u32, vec_of::<_, NURBS_DATA_MAX>(num(), 1))
            .prop_map(|(offset, values)| GroupCmd::NurbsData(NurbsData { offset, values }))
            .boxed(),
        Just(GroupCmd::NurbsEnd).boxed(),
        (nums::<3>(), nums::<MAX_AXES>(), path_flags())
            .prop_map(|([id, feed, tolerance], targets, flags)| {
                GroupCmd::PathLine(PathLine {
                    id,
                    feed,
                    tolerance,
                    targets,
                    flags,
                })
            })
            .boxed(),
        (nums::<3>(), arc(), path_flags())
            .prop_map(|([id, feed, tolerance], arc, flags)| {
                GroupCmd::PathArc(PathArc {
                    id,
                    feed,
                    tolerance,
                    arc,
                    flags,
                })
            })
            .boxed(),
        (nums::<2>(), any::<bool>())
            .prop_map(|([id, seconds], last)| GroupCmd::PathDwell(PathDwell { id, seconds, last }))
            .boxed(),
        (nums::<3>(), nums::<3>())
            .prop_map(|(axes, normal)| GroupCmd::PathArcPlane(PathArcPlane { axes, normal }))
            .boxed(),
        (
            nums::<9>(),
            nums::<{ MAX_AXES - 3 }>(),
            (any::<bool>(), any::<bool>()),
            path_flags(),
        )
            .prop_map(|(a, helix, (rise, helix_relative), flags)| {
                GroupCmd::PathArcNormal(PathArcNormal {
                    id: a[0],
                    feed: a[1],
                    tolerance: a[2],
                    centre: [a[3], a[4], a[5]],
                    end: [a[6], a[7], a[8]],
                    helix,
                    rise,
                    helix_relative,
                    flags,
                })
            })
            .boxed(),
        (
            feed_limits(),
            nums::<7>(),
            (any::<bool>(), any::<bool>()),
            move_opts(),
        )
            .prop_map(|(limits, a, (rise, helix_relative), opts)| {
                GroupCmd::MoveCircularNormal(CircularNormalMove {
                    limits,
                    centre: [a[0], a[1], a[2]],
                    end: [a[3], a[4], a[5]],
                    turns: a[6],
                    rise,
                    helix_relative,
                    opts,
                })
            })
            .boxed(),
        (nums::<3>(), nums::<3>(), nums::<{ MAX_AXES - 3 }>())
            .prop_map(|(axes, normal, helix)| {
                GroupCmd::CircularPlane(CircularPlane {
                    plane: PathArcPlane { axes, normal },
                    helix,
                })
            })
            .boxed(),
        (nums::<3>(), 0u8..4)
            .prop_map(|([output, on, distance], when)| {
                GroupCmd::PathOutput(PathOutput {
                    output,
                    on,
                    distance,
                    when,
                })
            })
            .boxed(),
        (nums::<3>(), size(), num(), path_flags())
            .prop_map(|([id, feed, tolerance], size, fit_tolerance, flags)| {
                GroupCmd::PathNurbs(PathNurbs {
                    id,
                    feed,
                    tolerance,
                    size,
                    fit_tolerance,
                    flags,
                })
            })
            .boxed(),
        Just(GroupCmd::ApplyPath).boxed(),
        Just(GroupCmd::ApplyDims).boxed(),
        nums::<CMD_ARGS>()
            .prop_map(|targets| GroupCmd::PathMore(PathMore { targets }))
            .boxed(),
        num()
            .prop_map(|count| GroupCmd::PathRelease(PathRelease { count }))
            .boxed(),
    ])
    .boxed()
}

fn sync_cmd() -> BoxedStrategy<SyncCmd> {
    let table = 0..CAM_TABLES as u8;
    Union::new(vec![
        gear_in().prop_map(SyncCmd::GearIn).boxed(),
        (gear_in(), finite(), finite())
            .prop_map(|(gear, master_position, slave_position)| {
                SyncCmd::GearInPos(GearInPos {
                    gear,
                    master_position,
                    slave_position,
                })
            })
            .boxed(),
        Just(SyncCmd::GearOut).boxed(),
        (
            table.clone(),
            3..=CAM_MAX_POINTS as u16,
            any::<(bool, bool)>(),
        )
            .prop_map(|(table, points, (cubic, periodic))| {
                SyncCmd::CamTable(CamTable {
                    table,
                    points,
                    cubic,
                    periodic,
                })
            })
            .boxed(),
        (
            table.clone(),
            0..CAM_MAX_POINTS as u16,
            vec_of::<_, { crate::CAM_DATA_MAX }>((finite(), finite()).boxed(), 1),
        )
            .prop_map(|(table, first, points)| {
                SyncCmd::CamData(CamData {
                    table,
                    first,
                    points,
                })
            })
            .boxed(),
        (
            master(),
            proptest::collection::vec(finite(), 5),
            sync_limits().prop_filter("finite", |l| {
                l.vmax.is_finite() && l.amax.is_finite() && l.jerk.is_finite()
            }),
            any::<(bool, bool)>(),
        )
            .prop_map(|(master, v, limits, (at_cycle_end, relative))| {
                SyncCmd::CamIn(CamIn {
                    master,
                    table: v[0],
                    master_offset: v[1],
                    slave_offset: v[2],
                    master_scale: v[3],
                    slave_scale: v[4],
                    limits,
                    at_cycle_end,
                    relative,
                })
            })
            .boxed(),
        Just(SyncCmd::CamOut).boxed(),
        (nums::<3>(), any::<bool>(), any::<u32>())
            .prop_map(|([vmax, amax, low_water], pt, other)| {
                SyncCmd::PvtBegin(PvtBegin {
                    vmax,
                    amax,
                    low_water,
                    pt,
                    other_flags: other & !crate::PVT_PT,
                })
            })
            .boxed(),
        (
            vec_of::<_, { crate::PVT_POINTS_MAX }>(
                nums::<3>()
                    .prop_map(|[time, position, velocity]| PvtPoint {
                        time,
                        position,
                        velocity,
                    })
                    .boxed(),
                1,
            ),
            any::<bool>(),
        )
            .prop_map(|(points, last)| SyncCmd::PvtPoints(PvtPoints { points, last }))
            .boxed(),
        (0u32..1 << MAX_AXES)
            .prop_map(|mask| SyncCmd::PvtStart(PvtStart { mask }))
            .boxed(),
    ])
    .boxed()
}

fn io_cmd() -> BoxedStrategy<IoCmd> {
    let dir = prop_oneof![Just(Direction::Up), Just(Direction::Down)];
    let word = 0u32..1 << crate::OUTPUTS;
    Union::new(vec![
        (word.clone(), word)
            .prop_map(|(mask, value)| IoCmd::SetOutputs(SetOutputs { mask, value }))
            .boxed(),
        Just(IoCmd::ApplyConfig).boxed(),
        (
            0..COMPARE_CHANNELS as u8,
            prop_oneof![
                Just((CompareKind::Single, None)),
                dir.clone().prop_map(|d| (CompareKind::Single, Some(d))),
                dir.clone().prop_map(|d| (CompareKind::Series, Some(d))),
                dir.clone().prop_map(|d| (CompareKind::Table, Some(d))),
            ],
            nums::<6>(),
            any::<bool>(),
        )
            .prop_map(|(channel, (kind, direction), v, each)| {
                IoCmd::CompareArm(CompareArm {
                    channel,
                    kind,
                    direction,
                    output: v[0],
                    pulse_us: v[1],
                    low_water: v[2],
                    position: v[3],
                    pitch: v[4],
                    count: v[5],
                    each_turn: each && kind != CompareKind::Table,
                })
            })
            .boxed(),
        (
            0..COMPARE_CHANNELS as u8,
            dir,
            vec_of::<_, { crate::COMPARE_TABLE_MAX }>(num(), 1),
        )
            .prop_map(|(channel, direction, positions)| {
                IoCmd::CompareTable(CompareTable {
                    channel,
                    direction,
                    positions,
                })
            })
            .boxed(),
        (0..COMPARE_CHANNELS as u8)
            .prop_map(|channel| IoCmd::CompareDisarm(CompareDisarm { channel }))
            .boxed(),
        (
            0..PROBE_CHANNELS as u8,
            0..=PROBE_INDEX,
            prop_oneof![Just((true, false)), Just((false, true)), Just((true, true))],
            any::<bool>(),
            proptest::option::of(nums::<2>()),
            any::<bool>(),
        )
            .prop_map(|(channel, input, (rising, falling), continuous, w, halt)| {
                IoCmd::ProbeArm(ProbeArm {
                    channel,
                    input,
                    rising,
                    falling,
                    continuous,
                    window: w.map(|[lo, hi]| (lo, hi)),
                    halt,
                })
            })
            .boxed(),
        (0..PROBE_CHANNELS as u8)
            .prop_map(|channel| IoCmd::ProbeAbort(ProbeAbort { channel }))
            .boxed(),
    ])
    .boxed()
}

fn card_cmd() -> BoxedStrategy<CardCmd> {
    let kind = proptest::sample::select(ConfigKind::ALL);
    let category = proptest::sample::select(StopCategory::ALL);
    Union::new(vec![
        Just(CardCmd::Nop).boxed(),
        Just(CardCmd::ApplyCardConfig).boxed(),
        Just(CardCmd::ApplyAxisConfig).boxed(),
        Just(CardCmd::ApplyAxisFilter).boxed(),
        Just(CardCmd::ApplyAxisHoming).boxed(),
        Just(CardCmd::ApplyAxisSafety).boxed(),
        Just(CardCmd::ApplySafetyConfig).boxed(),
        category
            .prop_map(|category| CardCmd::EStop(EStop { category }))
            .boxed(),
        Just(CardCmd::SafetyReset).boxed(),
        any::<u32>()
            .prop_map(|id| CardCmd::HostAttach(Session { id }))
            .boxed(),
        any::<u32>()
            .prop_map(|id| CardCmd::HostDetach(Session { id }))
            .boxed(),
        (kind, any::<u16>())
            .prop_map(|(kind, index)| CardCmd::ReadConfig(ReadConfig { kind, index }))
            .boxed(),
        num()
            .prop_map(|scale| CardCmd::SetScale(SetScale { scale }))
            .boxed(),
    ])
    .boxed()
}

fn any_cmd() -> BoxedStrategy<Cmd> {
    let scope = prop_oneof![
        Just(ScopeCmd::Configure),
        Just(ScopeCmd::Arm),
        Just(ScopeCmd::Trigger),
        Just(ScopeCmd::Stop)
    ];
    prop_oneof![
        axis_cmd().prop_map(Cmd::Axis),
        group_cmd().prop_map(Cmd::Group),
        sync_cmd().prop_map(Cmd::Sync),
        io_cmd().prop_map(Cmd::Io),
        card_cmd().prop_map(Cmd::Card),
        scope.prop_map(Cmd::Scope),
    ]
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// Encode, then decode: the same command, its opcode and target kept; and through the
    /// ring entry's words.
    #[test]
    fn every_command_round_trips(cmd in any_cmd(), target in any::<u16>()) {
        let entry = cmd.command(target);
        prop_assert_eq!(entry.opcode, cmd.opcode() as u16);
        prop_assert_eq!(entry.axis, target);
        prop_assert_eq!(Cmd::from_command(&entry), Ok(cmd.clone()));
        let words = Command::from_words(&entry.to_words());
        prop_assert_eq!(Cmd::from_command(&words), Ok(cmd.clone()));
        prop_assert_eq!(family(cmd.opcode()), match cmd {
            Cmd::Axis(_) => Family::Axis,
            Cmd::Group(_) => Family::Group,
            Cmd::Sync(_) => Family::Sync,
            Cmd::Io(_) => Family::Io,
            Cmd::Card(_) => Family::Card,
            Cmd::Scope(_) => Family::Scope,
        });
    }

    /// Decoding any entry never panics, and what decodes encodes back to an entry that decodes
    /// to the same command.
    #[test]
    fn any_entry_decodes_or_is_refused(
        op in any::<u16>(),
        flags in any::<u32>(),
        args in proptest::collection::vec(any::<u64>().prop_map(f64::from_bits), CMD_ARGS),
    ) {
        let args: [f64; CMD_ARGS] = core::array::from_fn(|i| args[i]);
        let op = Opcode::ALL.get(op as usize % 80).map_or(op, |o| *o as u16);
        if let Ok(cmd) = Cmd::decode(op, flags, &args) {
            let again = cmd.command(0);
            let same = Cmd::from_command(&again).unwrap();
            // NaN arguments make `==` false: compare the entries' words.
            prop_assert_eq!(same.command(0).to_words(), again.to_words());
        }
    }
}

/// The decode error of an entry of `op` with `flags` and these leading arguments (zeros after).
fn refused(op: Opcode, flags: u32, lead: &[f64]) -> DecodeError {
    let mut args = [0.0; CMD_ARGS];
    args[..lead.len()].copy_from_slice(lead);
    Cmd::decode(op as u16, flags, &args).expect_err("refused")
}

fn arg(i: u8, fault: Fault, nack: NackCode) -> DecodeError {
    DecodeError {
        field: Field::Arg(i),
        fault,
        nack,
    }
}

fn flags(nack: NackCode) -> DecodeError {
    DecodeError::flags(nack)
}

#[test]
fn every_opcode_has_a_family_whose_decoder_knows_it() {
    for &op in Opcode::ALL {
        // Zeros decode for every opcode but those whose counts or codes cannot be 0.
        match Cmd::decode(op as u16, 0, &[0.0; CMD_ARGS]) {
            Ok(c) => assert_eq!(c.opcode(), op),
            Err(e) => assert_ne!(e.field, Field::Opcode, "{op:?}"),
        }
    }
    assert_eq!(
        Cmd::decode(0, 0, &[0.0; CMD_ARGS]),
        Err(DecodeError {
            field: Field::Opcode,
            fault: Fault::UnknownOpcode,
            nack: NackCode::UnknownOpcode
        })
    );
    assert_eq!(
        AxisCmd::decode(Opcode::GroupHalt, 0, &[0.0; CMD_ARGS])
            .unwrap_err()
            .nack,
        NackCode::UnknownOpcode
    );
}

#[test]
fn malformed_entries_give_their_fault_and_nack() {
    use Fault::*;
    use NackCode as N;
    use Opcode as O;
    let nan = f64::NAN;
    let cases: &[(Opcode, u32, &[f64], DecodeError)] = &[
        // Card, safety
        (O::EStop, 0, &[nan], arg(0, NotFinite, N::NotFinite)),
        (O::EStop, 0, &[3.0], arg(0, UnknownCode, N::BadCategory)),
        (O::EStop, 0, &[0.5], arg(0, UnknownCode, N::BadCategory)),
        (O::ReadConfig, 0, &[0.0], arg(0, UnknownCode, N::ConfigKind)),
        (O::ReadConfig, 0, &[2.5], arg(0, NotInteger, N::ConfigKind)),
        (O::ReadConfig, 0, &[nan], arg(0, NotFinite, N::ConfigKind)),
        (
            O::ReadConfig,
            0,
            &[2.0, -1.0],
            arg(1, OutOfRange, N::ConfigKind),
        ),
        (
            O::ReadConfig,
            0,
            &[2.0, 70_000.0],
            arg(1, OutOfRange, N::ConfigKind),
        ),
        // I/O
        (
            O::SetOutputs,
            0,
            &[65_536.0, 0.0],
            arg(0, OutOfRange, N::PathOutput),
        ),
        (
            O::SetOutputs,
            0,
            &[1.0, 0.5],
            arg(1, NotInteger, N::PathOutput),
        ),
        (
            O::SetOutputs,
            0,
            &[1.0, nan],
            arg(1, NotFinite, N::PathOutput),
        ),
        (O::CompareDisarm, 0, &[nan], arg(0, NotFinite, N::NotFinite)),
        (
            O::CompareDisarm,
            0,
            &[4.0],
            arg(0, OutOfRange, N::IoChannel),
        ),
        (O::ProbeAbort, 0, &[-0.5], arg(0, NotInteger, N::IoChannel)),
        (O::CompareArm, 1 << 9, &[0.0], flags(N::CompareMode)),
        (
            O::CompareArm,
            3 | raw::MC_CMP_DIR_POS,
            &[0.0],
            flags(N::CompareMode),
        ),
        (
            O::CompareArm,
            raw::MC_CMP_MODE_SERIES,
            &[0.0],
            flags(N::CompareMode),
        ),
        (
            O::CompareArm,
            raw::MC_CMP_MODE_TABLE | raw::MC_CMP_DIR_POS | raw::MC_CMP_DIR_NEG,
            &[0.0],
            flags(N::CompareMode),
        ),
        (
            O::CompareArm,
            raw::MC_CMP_DIR_POS,
            &[5.0],
            arg(0, OutOfRange, N::IoChannel),
        ),
        (
            O::CompareTable,
            raw::MC_CMP_DIR_POS,
            &[0.0, nan],
            arg(1, NotFinite, N::NotFinite),
        ),
        (
            O::CompareTable,
            raw::MC_CMP_DIR_POS,
            &[0.0, 0.0],
            arg(1, OutOfRange, N::CompareMode),
        ),
        (
            O::CompareTable,
            raw::MC_CMP_DIR_POS,
            &[0.0, 13.0],
            arg(1, OutOfRange, N::CompareMode),
        ),
        (
            O::CompareTable,
            raw::MC_CMP_DIR_POS,
            &[0.0, 1.5],
            arg(1, NotInteger, N::CompareMode),
        ),
        (O::CompareTable, 0, &[0.0, 1.0], flags(N::CompareMode)),
        (
            O::CompareTable,
            raw::MC_CMP_DIR_POS | raw::MC_CMP_DIR_NEG,
            &[0.0, 1.0],
            flags(N::CompareMode),
        ),
        (O::ProbeArm, 0, &[0.0, 1.0], flags(N::ProbeInput)),
        (O::ProbeArm, 1 << 5 | 1, &[0.0, 1.0], flags(N::ProbeInput)),
        (O::ProbeArm, 1, &[0.0, nan], arg(1, NotFinite, N::NotFinite)),
        (
            O::ProbeArm,
            1,
            &[0.0, 17.0],
            arg(1, OutOfRange, N::ProbeInput),
        ),
        (
            O::ProbeArm,
            1,
            &[9.0, 1.0],
            arg(0, OutOfRange, N::IoChannel),
        ),
        // Groups
        (
            O::NurbsData,
            0,
            &[nan, 1.0],
            arg(0, NotFinite, N::NurbsSequence),
        ),
        (
            O::NurbsData,
            0,
            &[0.5, 1.0],
            arg(0, NotInteger, N::NurbsSequence),
        ),
        (
            O::NurbsData,
            0,
            &[0.0, 0.0],
            arg(1, OutOfRange, N::NurbsSequence),
        ),
        (
            O::NurbsData,
            0,
            &[0.0, 13.0],
            arg(1, OutOfRange, N::NurbsSequence),
        ),
        (
            O::NurbsData,
            0,
            &[2e9, 1.0],
            arg(0, OutOfRange, N::NurbsSequence),
        ),
        (
            O::GroupPtpLimits,
            0,
            &[0.0, nan],
            arg(1, NotFinite, N::NotFinite),
        ),
        (
            O::GroupPtpLimits,
            0,
            &[0.5, 1.0],
            arg(0, NotInteger, N::BadConfig),
        ),
        (
            O::GroupPtpLimits,
            0,
            &[0.0, 0.0],
            arg(1, OutOfRange, N::BadConfig),
        ),
        (
            O::GroupPtpLimits,
            0,
            &[0.0, 4.0],
            arg(1, OutOfRange, N::BadConfig),
        ),
        // Sync
        (
            O::GearIn,
            0,
            &[1.0, 1.0, 1.0, nan],
            arg(3, NotFinite, N::NotFinite),
        ),
        (O::GearIn, 4, &[1.0, 1.0, 1.0], flags(N::SyncMaster)),
        (
            O::GearIn,
            0,
            &[1.5, 1.0, 1.0],
            arg(0, NotInteger, N::SyncMaster),
        ),
        (
            O::GearIn,
            0,
            &[8.0, 1.0, 1.0],
            arg(0, OutOfRange, N::SyncMaster),
        ),
        (
            O::GearIn,
            2,
            &[2.0, 1.0, 1.0],
            arg(0, OutOfRange, N::SyncMaster),
        ),
        (
            O::GearInPos,
            0,
            &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0, nan],
            arg(7, NotFinite, N::NotFinite),
        ),
        (O::CamIn, 1 << 6, &[1.0], flags(N::SyncMaster)),
        (O::CamIn, 0, &[-1.0], arg(0, OutOfRange, N::SyncMaster)),
        (
            O::CamIn,
            0,
            &[1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, nan],
            arg(8, NotFinite, N::NotFinite),
        ),
        (O::CamTable, 0, &[0.0, nan], arg(1, NotFinite, N::NotFinite)),
        (O::CamTable, 0, &[4.0, 2.0], arg(0, OutOfRange, N::CamTable)),
        (
            O::CamTable,
            raw::MC_CAM_CUBIC,
            &[0.0, 2.0],
            arg(1, OutOfRange, N::CamTable),
        ),
        (
            O::CamTable,
            0,
            &[0.0, 1025.0],
            arg(1, OutOfRange, N::CamTable),
        ),
        (O::CamTable, 1 << 2, &[0.0, 2.0], flags(N::CamTable)),
        (
            O::CamData,
            0,
            &[
                0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nan,
            ],
            arg(13, NotFinite, N::NotFinite),
        ),
        (
            O::CamData,
            0,
            &[4.0, 0.0, 1.0],
            arg(0, OutOfRange, N::CamTable),
        ),
        (
            O::CamData,
            0,
            &[0.0, 0.0, 6.0],
            arg(2, OutOfRange, N::CamSequence),
        ),
        (
            O::CamData,
            0,
            &[0.0, 0.0, 0.0],
            arg(2, OutOfRange, N::CamSequence),
        ),
        (
            O::CamData,
            0,
            &[0.0, 1024.0, 1.0],
            arg(1, OutOfRange, N::CamSequence),
        ),
        (O::PvtPoints, 0, &[nan], arg(0, NotFinite, N::NotFinite)),
        (O::PvtPoints, 0, &[5.0], arg(0, OutOfRange, N::OutOfRange)),
        (O::PvtPoints, 0, &[2.5], arg(0, NotInteger, N::OutOfRange)),
        (O::PvtPoints, PVT_LAST << 1, &[1.0], flags(N::BadConfig)),
        (O::PvtStart, 0, &[nan], arg(0, NotFinite, N::NotFinite)),
        (O::PvtStart, 0, &[256.0], arg(0, OutOfRange, N::BadAxis)),
        (O::PvtStart, 0, &[0.25], arg(0, NotInteger, N::BadAxis)),
        // Layout 1.10: the handwheel's input, ratio and detent.
        (
            O::Handwheel,
            0,
            &[2.0, 1.0, 4.0],
            arg(0, OutOfRange, N::HandwheelInput),
        ),
        (
            O::Handwheel,
            0,
            &[0.5, 1.0, 4.0],
            arg(0, NotInteger, N::HandwheelInput),
        ),
        (
            O::Handwheel,
            0,
            &[nan, 1.0, 4.0],
            arg(0, NotFinite, N::NotFinite),
        ),
        (
            O::Handwheel,
            0,
            &[1.0, 0.0, 4.0],
            arg(1, OutOfRange, N::HandwheelRatio),
        ),
        (
            O::Handwheel,
            0,
            &[1.0, 10001.0, 4.0],
            arg(1, OutOfRange, N::HandwheelRatio),
        ),
        (
            O::Handwheel,
            0,
            &[1.0, -2.5, 4.0],
            arg(1, NotInteger, N::HandwheelRatio),
        ),
        (
            O::Handwheel,
            0,
            &[1.0, nan, 4.0],
            arg(1, NotFinite, N::NotFinite),
        ),
        (
            O::Handwheel,
            0,
            &[1.0, 10.0, 0.0],
            arg(2, OutOfRange, N::HandwheelRatio),
        ),
        (
            O::Handwheel,
            0,
            &[1.0, 10.0, 1025.0],
            arg(2, OutOfRange, N::HandwheelRatio),
        ),
    ];
    for (op, f, lead, want) in cases {
        assert_eq!(
            refused(*op, *f, lead),
            *want,
            "{op:?} flags {f:#x} args {lead:?}"
        );
    }
}

/// Plain numbers are never refused by decoding (the card checks them): NaN and infinities in
/// every argument of the commands that carry only numbers decode.
#[test]
fn plain_numbers_are_the_cards_to_check() {
    use Opcode as O;
    for op in [
        O::MoveAbsolute,
        O::MoveVelocity,
        O::Jog,
        O::Halt,
        O::Home,
        O::SetPosition,
        O::SetScale,
        O::SetModulo,
        O::GroupMoveLinear,
        O::GroupMoveCircular,
        O::GroupMovePtp,
        O::GroupSetOverride,
        O::NurbsBegin,
        O::PathLine,
        O::PathArc,
        O::PathDwell,
        O::PathOutput,
        O::PathNurbs,
        O::PathArcPlane,
        O::PathArcNormal,
        O::GroupMoveCircularNormal,
        O::GroupCircularPlane,
        O::PathMore,
        O::PathRelease,
        O::PvtBegin,
    ] {
        for x in [f64::NAN, f64::INFINITY, -1e300, 0.5] {
            assert!(
                Cmd::decode(op as u16, !0, &[x; CMD_ARGS]).is_ok(),
                "{op:?} {x}"
            );
        }
    }
}

/// The flags a command does not read are ignored, and those it keeps for the card to refuse
/// are kept (PVT begin's).
#[test]
fn pvt_begin_keeps_unknown_flags_for_the_card() {
    let c = Cmd::decode(
        Opcode::PvtBegin as u16,
        0x10 | crate::PVT_PT,
        &[0.0; CMD_ARGS],
    );
    assert_eq!(
        c,
        Ok(Cmd::Sync(SyncCmd::PvtBegin(PvtBegin {
            vmax: 0.0,
            amax: 0.0,
            low_water: 0.0,
            pt: true,
            other_flags: 0x10,
        })))
    );
}
