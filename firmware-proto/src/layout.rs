//! Byte offsets of every field of the window, derived from the generated bindings.
//!
//! Offsets are `const`s computed with `offset_of!` on the bindgen structs, so the C header stays
//! the only source of truth; the asserts at the bottom pin the properties the protocol relies on
//! (entry sizes, one index per cache line, word alignment).
#![allow(missing_docs)]

use crate::block::{BlockAt, Blocks};
use crate::raw::*;
use crate::{MAX_AXES, MAX_GROUPS};
use core::mem::{offset_of, size_of};

macro_rules! off {
    ($($path:tt)+) => { offset_of!(mc_dpram, $($path)+) };
}

// identity (card writes)
pub const MAGIC: usize = off!(identity.magic);
/// `layout_major | layout_minor << 16` read as one 32-bit word.
pub const LAYOUT: usize = off!(identity.layout_major);
pub const FW_VERSION: usize = off!(identity.fw_version);
pub const CAPABILITIES: usize = off!(identity.capabilities);
pub const NUM_AXES: usize = off!(identity.num_axes);
pub const SERVO_RATE_HZ: usize = off!(identity.servo_rate_hz);
pub const CMD_RING_LEN: usize = off!(identity.cmd_ring_len);
pub const EVT_RING_LEN: usize = off!(identity.evt_ring_len);
pub const CARD_STATE: usize = off!(identity.card_state);

// host control (host writes)
pub const HEARTBEAT: usize = off!(host.heartbeat);
pub const HOST_PERIOD_US: usize = off!(host.host_period_us);
pub const DOORBELL: usize = off!(host.doorbell);
pub const IRQ_MASK: usize = off!(host.irq_mask);
pub const HOST_TIME_MS: usize = off!(host.host_time_ms);

// card control (card writes)
pub const TICK: usize = off!(card.tick);
pub const IRQ_COUNT: usize = off!(card.irq_count);
pub const EVENTS_LOST: usize = off!(card.events_lost);
pub const CMDS_ACCEPTED: usize = off!(card.cmds_accepted);
/// Layout 1.4: the card's accesses to the window out of range or misaligned.
pub const BAD_ACCESSES: usize = off!(card.bad_accesses);
/// Layout 1.4: events that found the firmware's outbox full.
pub const OUTBOX_LOST: usize = off!(card.outbox_lost);
/// Layout 1.4: safety events that found the safety layer's event buffer full.
pub const SAFETY_EVENTS_LOST: usize = off!(card.safety_events_lost);
/// `card.outputs` (layout 1.6): the digital outputs.
pub const OUTPUTS: usize = off!(card.outputs);
/// `card.inputs` (layout 1.7): the debounced digital inputs.
pub const INPUTS: usize = off!(card.inputs);
/// `card.inputs_raw` (layout 1.7): the digital inputs as sampled.
pub const INPUTS_RAW: usize = off!(card.inputs_raw);

// rings
pub const CMD_HEAD: usize = off!(cmd_head.value);
pub const CMD_TAIL: usize = off!(cmd_tail.value);
pub const EVT_HEAD: usize = off!(evt_head.value);
pub const EVT_TAIL: usize = off!(evt_tail.value);
pub const CMD_RING: usize = off!(cmd_ring);
pub const EVT_RING: usize = off!(evt_ring);
pub const CMD_BYTES: usize = size_of::<mc_cmd>();
pub const EVT_BYTES: usize = size_of::<mc_event>();

// configuration (host writes)
/// `card_config`.
pub const CARD_CONFIG: BlockAt<mc_card_config> = BlockAt::new(off!(card_config));
/// `axis_config[axis]`.
pub const AXIS_CONFIG: Blocks<mc_axis_config, MAX_AXES> = Blocks::new(off!(axis_config));
pub const AXIS_CONFIG_BYTES: usize = size_of::<mc_axis_config>();

// status (card writes)
pub const AXIS_STATUS: usize = off!(axis_status);
pub const AXIS_STATUS_BYTES: usize = size_of::<mc_axis_status>();
pub const STATUS_SEQ: usize = offset_of!(mc_axis_status, seq);
pub const STATUS_PAYLOAD: usize = offset_of!(mc_axis_status, p);
pub const STATUS_WORDS: usize = MC_STATUS_WORDS as usize;

/// Offset of the seqlock word of `axis_status[axis]`.
pub const fn axis_status(axis: usize) -> usize {
    AXIS_STATUS + axis * AXIS_STATUS_BYTES
}

// axis filters, group configuration (host writes) and group status (card writes)
pub const GROUP_STATUS: usize = off!(group_status);
pub const GROUP_STATUS_BYTES: usize = size_of::<mc_group_status>();

/// `axis_filter[axis]`.
pub const AXIS_FILTER: Blocks<mc_axis_filter, MAX_AXES> = Blocks::new(off!(axis_filter));
/// `group_config[group]`.
pub const GROUP_CONFIG: Blocks<mc_group_config, MAX_GROUPS> = Blocks::new(off!(group_config));
/// `axis_pdplus[axis]`.
pub const AXIS_PDPLUS: Blocks<mc_axis_pdplus, MAX_AXES> = Blocks::new(off!(axis_pdplus));

/// Offset of the seqlock word of `group_status[group]`.
pub const fn group_status(group: usize) -> usize {
    GROUP_STATUS + group * GROUP_STATUS_BYTES
}

const _: () = {
    assert!(offset_of!(mc_group_status, p) == STATUS_PAYLOAD);
    assert!(size_of::<mc_group_status_payload>() == STATUS_WORDS * 8);
    // Layout 1.2 put the snap corrections in words 7 and 8.
    assert!(offset_of!(mc_group_status_payload, snap_last) == 7 * 8);
    assert!(offset_of!(mc_group_status_payload, snap_max) == 8 * 8);
    assert!(GROUP_STATUS.is_multiple_of(64) && GROUP_STATUS_BYTES.is_multiple_of(64));
    assert!(offset_of!(mc_group_config, axes).is_multiple_of(4));
    // Layout 1.0 offsets are unchanged by the 1.1 additions.
    assert!(
        CMD_RING == 512
            && EVT_RING == 8704
            && AXIS_STATUS == 17984
            && AXIS_FILTER.at(0).offset() == 17984 + 8 * 256
    );
    assert!(offset_of!(mc_axis_status_payload, u_request) == 20 * 8);
};

// safety (layout 1.1, appended after the group blocks)
/// `safety` (the card-wide safety configuration).
pub const SAFETY_CONFIG: BlockAt<mc_safety_config> = BlockAt::new(off!(safety));
pub const AXIS_SAFETY_BYTES: usize = size_of::<mc_axis_safety>();
/// `axis_safety[axis]`.
pub const AXIS_SAFETY: Blocks<mc_axis_safety, MAX_AXES> = Blocks::new(off!(axis_safety));
pub const SAFETY_STATUS: usize = off!(safety_status);

// homing (layout 1.5, appended after the safety status)
/// `axis_homing[axis]`.
pub const AXIS_HOMING: Blocks<mc_axis_homing, MAX_AXES> = Blocks::new(off!(axis_homing));
pub const AXIS_HOMING_BYTES: usize = size_of::<mc_axis_homing>();

const _: () = {
    assert!(AXIS_HOMING_BYTES == 128 && AXIS_HOMING.at(0).offset().is_multiple_of(64));
    assert!(AXIS_HOMING.at(0).offset() >= SAFETY_STATUS + size_of::<mc_safety_status>());
    assert!(AXIS_HOMING.at(MAX_AXES - 1).offset() + AXIS_HOMING_BYTES <= crate::DPRAM_SIZE);
};

// path (layout 1.6, appended after the homing blocks)
/// `group_path[group]`.
pub const GROUP_PATH: Blocks<mc_group_path, MAX_GROUPS> = Blocks::new(off!(group_path));
pub const GROUP_PATH_BYTES: usize = size_of::<mc_group_path>();

const _: () = {
    assert!(GROUP_PATH.at(0).offset().is_multiple_of(8));
    assert!(GROUP_PATH.at(0).offset() >= AXIS_HOMING.at(MAX_AXES - 1).offset() + AXIS_HOMING_BYTES);
    assert!(GROUP_PATH.at(MAX_GROUPS - 1).offset() + GROUP_PATH_BYTES <= crate::DPRAM_SIZE);
};

// digital I/O, compare and probes (layout 1.7, appended after the path blocks)
/// `io_config`.
pub const IO_CONFIG: BlockAt<mc_io_config> = BlockAt::new(off!(io_config));
/// `compare_status[channel]`.
pub const COMPARE_STATUS: Blocks<mc_compare_status, { MC_COMPARE_CHANNELS as usize }> =
    Blocks::new(off!(compare_status));
/// `probe_status[channel]`.
pub const PROBE_STATUS: Blocks<mc_probe_status, { MC_PROBE_CHANNELS as usize }> =
    Blocks::new(off!(probe_status));
/// What layout 1.7 added to the window, bytes.
pub const LAYOUT_1_7_BYTES: usize = size_of::<mc_io_config>()
    + MC_COMPARE_CHANNELS as usize * size_of::<mc_compare_status>()
    + MC_PROBE_CHANNELS as usize * size_of::<mc_probe_status>();

const _: () = {
    assert!(IO_CONFIG.offset() >= GROUP_PATH.at(MAX_GROUPS - 1).offset() + GROUP_PATH_BYTES);
    assert!(IO_CONFIG.offset().is_multiple_of(8));
    assert!(size_of::<mc_io_config>() == 64 && size_of::<mc_compare_status>() == 56);
    assert!(size_of::<mc_probe_status>() == 96);
    assert!(LAYOUT_1_7_BYTES < 2048);
    assert!(
        PROBE_STATUS.at(MC_PROBE_CHANNELS as usize - 1).offset() + size_of::<mc_probe_status>()
            <= crate::DPRAM_SIZE
    );
    // Layout 1.7 took two reserved words of the card control block; it did not move or grow.
    assert!(INPUTS == OUTPUTS + 4 && INPUTS_RAW == OUTPUTS + 8);
};

/// Layout 1.7 (sync): the card-written synchronised-motion status (aux encoders, gear ratios).
pub const SYNC_STATUS: BlockAt<mc_sync_status> = BlockAt::new(off!(sync_status));
/// Its size.
pub const SYNC_STATUS_BYTES: usize = size_of::<mc_sync_status>();
const _: () = {
    assert!(SYNC_STATUS.offset().is_multiple_of(8));
    assert!(SYNC_STATUS.offset() >= GROUP_PATH.at(MAX_GROUPS - 1).offset() + GROUP_PATH_BYTES);
    assert!(SYNC_STATUS.offset() + SYNC_STATUS_BYTES <= crate::DPRAM_SIZE);
};

/// Layout 1.8: the scope's configuration (host writes).
pub const SCOPE_CONFIG: BlockAt<mc_scope_config> = BlockAt::new(off!(scope_config));
/// The scope's status (card writes).
pub const SCOPE_STATUS: BlockAt<mc_scope_status> = BlockAt::new(off!(scope_status));
/// The scope ring's indices and entries.
pub const SCOPE_HEAD: usize = off!(scope_head.value);
pub const SCOPE_TAIL: usize = off!(scope_tail.value);
pub const SCOPE_RING: usize = off!(scope_ring);
pub const SCOPE_SAMPLE_BYTES: usize = size_of::<mc_scope_sample>();
/// `scope_status.lost`, `samples` and `state`, read on their own by the host.
pub const SCOPE_LOST: usize = off!(scope_status.lost);
pub const SCOPE_SAMPLES: usize = off!(scope_status.samples);
pub const SCOPE_STATE: usize = off!(scope_status.state);
const _: () = {
    // Layout 1.8 appended: everything before it is where layout 1.7 put it.
    assert!(SCOPE_CONFIG.offset() == 27088 && SYNC_STATUS.offset() + SYNC_STATUS_BYTES <= 27088);
    assert!(size_of::<mc_scope_config>() == 144 && size_of::<mc_scope_status>() == 64);
    assert!(SCOPE_STATUS.offset().is_multiple_of(8) && SCOPE_LOST.is_multiple_of(8));
    // One ring index per 64-byte line, entries word-aligned.
    assert!(SCOPE_HEAD.is_multiple_of(64) && SCOPE_TAIL == SCOPE_HEAD + 64);
    assert!(
        SCOPE_RING == SCOPE_TAIL + 64 && SCOPE_SAMPLE_BYTES == 8 * (1 + MC_SCOPE_CHANNELS as usize)
    );
    assert!(MC_SCOPE_RING_LEN.is_power_of_two());
    // At 20 kHz the ring holds at least 100 ms of samples.
    assert!(MC_SCOPE_RING_LEN as u64 * 10 >= MC_SERVO_RATE_MAX_HZ as u64);
    assert!(SCOPE_RING + MC_SCOPE_RING_LEN as usize * SCOPE_SAMPLE_BYTES <= crate::DPRAM_SIZE);
};
/// Layout 1.9: a compensation table read back (`MC_OP_COMP_READ`). Card writes.
pub const COMP_READBACK: BlockAt<mc_comp_readback> = BlockAt::new(off!(comp_readback));
/// Its size.
pub const COMP_READBACK_BYTES: usize = size_of::<mc_comp_readback>();
const _: () = {
    // Layout 1.9 appended after the scope ring: everything before it where 1.8 put it.
    assert!(COMP_READBACK.offset() == SCOPE_RING + MC_SCOPE_RING_LEN as usize * SCOPE_SAMPLE_BYTES);
    assert!(COMP_READBACK.offset().is_multiple_of(8));
    assert!(COMP_READBACK.offset() + COMP_READBACK_BYTES <= crate::DPRAM_SIZE);
    assert!(size_of::<mc_comp_point>() == 24);
};
/// Layout 1.10: the gantries' status blocks (`mc_gantry_status`). Card writes.
pub const GANTRY_STATUS: Blocks<mc_gantry_status, { MC_MAX_GANTRIES as usize }> =
    Blocks::new(off!(gantry_status));
/// One block's size.
pub const GANTRY_STATUS_BYTES: usize = size_of::<mc_gantry_status>();
const _: () = {
    // Layout 1.10 appended after the compensation read-back.
    assert!(GANTRY_STATUS.at(0).offset() == COMP_READBACK.offset() + COMP_READBACK_BYTES);
    assert!(GANTRY_STATUS.at(0).offset().is_multiple_of(8));
    assert!(
        GANTRY_STATUS.at(MC_MAX_GANTRIES as usize - 1).offset() + GANTRY_STATUS_BYTES
            <= crate::DPRAM_SIZE
    );
};
/// Layout 1.11: each axis's PID + feed-forward gains (`mc_axis_pidff`). Host writes.
pub const AXIS_PIDFF: Blocks<mc_axis_pidff, MAX_AXES> = Blocks::new(off!(axis_pidff));
/// Layout 1.11: each axis's biquad filters (`mc_servo_filters`). Card writes.
pub const SERVO_FILTERS: Blocks<mc_servo_filters, MAX_AXES> = Blocks::new(off!(servo_filters));
const _: () = {
    // Layout 1.11 appended after the gantries' status.
    assert!(
        AXIS_PIDFF.at(0).offset()
            == GANTRY_STATUS.at(0).offset() + MC_MAX_GANTRIES as usize * GANTRY_STATUS_BYTES
    );
    assert!(AXIS_PIDFF.at(0).offset().is_multiple_of(8));
    assert!(SERVO_FILTERS.at(0).offset().is_multiple_of(8));
    assert!(
        SERVO_FILTERS.at(MAX_AXES - 1).offset() + size_of::<mc_servo_filters>()
            <= crate::DPRAM_SIZE
    );
};
/// Layout 1.11: analog I/O and the PSO (`mc_analog_status`). Card writes.
pub const ANALOG_STATUS: BlockAt<mc_analog_status> = BlockAt::new(off!(analog_status));
/// Its size.
pub const ANALOG_STATUS_BYTES: usize = size_of::<mc_analog_status>();
const _: () = {
    // Layout 1.11 appended after the servo filters.
    assert!(
        ANALOG_STATUS.offset()
            == SERVO_FILTERS.at(MAX_AXES - 1).offset() + size_of::<mc_servo_filters>()
    );
    assert!(ANALOG_STATUS.offset().is_multiple_of(8));
    assert!(ANALOG_STATUS.offset() + ANALOG_STATUS_BYTES <= crate::DPRAM_SIZE);
};
/// Layout 1.12: the card's name, serial and place on the sync bus (`mc_card_info`). Card
/// writes.
pub const CARD_INFO: BlockAt<mc_card_info> = BlockAt::new(off!(card_info));
/// Its size.
pub const CARD_INFO_BYTES: usize = size_of::<mc_card_info>();
const _: () = {
    // Layout 1.12 appended after the analog status.
    assert!(CARD_INFO.offset() == ANALOG_STATUS.offset() + ANALOG_STATUS_BYTES);
    assert!(CARD_INFO.offset().is_multiple_of(8));
    assert!(CARD_INFO.offset() + CARD_INFO_BYTES <= crate::DPRAM_SIZE);
};
/// Layout 1.12: the frequency-response sweep (`mc_freq_status`). Card writes.
pub const FREQ_STATUS: BlockAt<mc_freq_status> = BlockAt::new(off!(freq_status));
const _: () = {
    // Layout 1.12 appended after the card's information.
    assert!(FREQ_STATUS.offset() == CARD_INFO.offset() + CARD_INFO_BYTES);
    assert!(FREQ_STATUS.offset().is_multiple_of(8));
    assert!(FREQ_STATUS.offset() + size_of::<mc_freq_status>() <= crate::DPRAM_SIZE);
};
/// Layout 1.14: `group_dims[group]`, the groups' path dimensions (paths across cards). Host
/// writes.
pub const GROUP_DIMS: Blocks<mc_group_dims, MAX_GROUPS> = Blocks::new(off!(group_dims));
/// Its size.
pub const GROUP_DIMS_BYTES: usize = size_of::<mc_group_dims>();
/// Dimensions of a path across cards.
pub const PATH_MAX_DIMS: usize = MC_PATH_MAX_DIMS as usize;
/// Segments a group stages before they are released.
pub const PATH_STAGE_LEN: usize = MC_PATH_STAGE_LEN as usize;
const _: () = {
    // Layout 1.14 appended after the frequency sweep.
    assert!(GROUP_DIMS.at(0).offset() == FREQ_STATUS.offset() + size_of::<mc_freq_status>());
    assert!(GROUP_DIMS.at(0).offset().is_multiple_of(8));
    assert!(GROUP_DIMS.at(MAX_GROUPS - 1).offset() + GROUP_DIMS_BYTES <= crate::DPRAM_SIZE);
};
// Layout 1.8: the configuration read-back grows nothing. The scale took a reserved word of
// `mc_axis_config` (its size and every other field's offset as in 1.7), and the read-back
// writes into the configuration blocks.
const _: () = {
    assert!(size_of::<mc_axis_config>() == 128);
    assert!(offset_of!(mc_axis_config, jog_jerk) == 104);
    assert!(offset_of!(mc_axis_config, scale) == 112);
    assert!(offset_of!(mc_axis_config, modulo) == 120); // layout 1.10: its reserved word
};

/// The card-written safety status block (`mc_safety_status`).
pub mod safety_status {
    use super::*;
    const B: usize = off!(safety_status);
    pub const FAULTS: usize = B + offset_of!(mc_safety_status, faults);
    pub const WATCHDOG_ARMED: usize = B + offset_of!(mc_safety_status, watchdog_armed);
    pub const LAST_HEARTBEAT_TICK: usize = B + offset_of!(mc_safety_status, last_heartbeat_tick);
    pub const WATCHDOG_TRIP_TICK: usize = B + offset_of!(mc_safety_status, watchdog_trip_tick);
    pub const PROTOCOL_ERRORS: usize = B + offset_of!(mc_safety_status, protocol_errors);
    pub const TRIP_HEARTBEAT_TICK: usize = B + offset_of!(mc_safety_status, trip_heartbeat_tick);
    pub const SESSION: usize = B + offset_of!(mc_safety_status, session);
    pub const HOST_CHANGES: usize = B + offset_of!(mc_safety_status, host_changes);
    pub const LATE_HEARTBEATS: usize = B + offset_of!(mc_safety_status, late_heartbeats);
    pub const MAX_HEARTBEAT_GAP_US: usize = B + offset_of!(mc_safety_status, max_heartbeat_gap_us);
    pub const ATTACH_TICK: usize = B + offset_of!(mc_safety_status, attach_tick);
    const STOP_TICK: usize = B + offset_of!(mc_safety_status, stop_tick);
    const REST_TICK: usize = B + offset_of!(mc_safety_status, rest_tick);
    const RAMP_TIME: usize = B + offset_of!(mc_safety_status, ramp_time);
    /// `stop_tick[axis]`.
    pub const fn stop_tick(axis: usize) -> usize {
        STOP_TICK + 8 * axis
    }
    /// `rest_tick[axis]`.
    pub const fn rest_tick(axis: usize) -> usize {
        REST_TICK + 8 * axis
    }
    /// `ramp_time[axis]`.
    pub const fn ramp_time(axis: usize) -> usize {
        RAMP_TIME + 8 * axis
    }
}

// Layout 1.1 only appended: every offset of layout 1.0 is where it was.
const _: () = {
    assert!(HEARTBEAT == 64 && HOST_PERIOD_US == 68 && DOORBELL == 72 && IRQ_MASK == 76);
    assert!(TICK == 128 && IRQ_COUNT == 136 && EVENTS_LOST == 140 && CMDS_ACCEPTED == 144);
    // Layout 1.4 took reserved words of the card control block; the block did not move or grow.
    assert!(BAD_ACCESSES == 148 && OUTBOX_LOST == 152 && SAFETY_EVENTS_LOST == 156);
    assert!(size_of::<mc_card_ctrl>() == 64);
    assert!(CMD_HEAD == 256 && CMD_TAIL == 320 && EVT_HEAD == 384 && EVT_TAIL == 448);
    assert!(CMD_RING == 512 && EVT_RING == 8704);
    assert!(
        CARD_CONFIG.offset() == 16896
            && AXIS_CONFIG.at(0).offset() == 16960
            && AXIS_CONFIG_BYTES == 128
    );
    assert!(AXIS_STATUS == 17984 && AXIS_STATUS_BYTES == 256 && STATUS_PAYLOAD == 8);
    assert!(SAFETY_CONFIG.offset() > AXIS_PDPLUS.at(0).offset());
    assert!(offset_of!(mc_axis_status_payload, move_time) == 18 * 8);
    assert!(offset_of!(mc_axis_status_payload, stop_reason) == 19 * 8);
    assert!(offset_of!(mc_axis_status_payload, io) == 19 * 8 + 4);
    assert!(offset_of!(mc_axis_status_payload, comp_pos) == 23 * 8);
    assert!(offset_of!(mc_axis_status_payload, checksum) == 24 * 8);
    assert!(AXIS_SAFETY_BYTES == 128 && AXIS_SAFETY.at(0).offset().is_multiple_of(64));
    assert!(
        SAFETY_STATUS.is_multiple_of(64) && safety_status::LAST_HEARTBEAT_TICK.is_multiple_of(8)
    );
};

const _: () = {
    assert!(MAGIC == 0);
    assert!(off!(identity.layout_minor) == LAYOUT + 2);
    assert!(CMD_BYTES == 128 && EVT_BYTES == 32);
    assert!(CMD_RING.is_multiple_of(64) && EVT_RING.is_multiple_of(64));
    assert!(CMD_TAIL - CMD_HEAD == 64 && EVT_HEAD - CMD_TAIL == 64 && EVT_TAIL - EVT_HEAD == 64);
    assert!(MC_CMD_RING_LEN.is_power_of_two() && MC_EVT_RING_LEN.is_power_of_two());
    assert!(size_of::<mc_axis_status_payload>() == STATUS_WORDS * 8);
    assert!(
        STATUS_PAYLOAD.is_multiple_of(8)
            && AXIS_STATUS.is_multiple_of(64)
            && AXIS_STATUS_BYTES.is_multiple_of(64)
    );

    assert!(TICK.is_multiple_of(8));
};
