/*
 * motioncard.h: the C ABI of the motion-card SDK (libmotioncard).
 *
 * Build against it with pkg-config:
 *     cc app.c $(pkg-config --cflags --libs motioncard)
 *
 * Conventions
 * - Every function returns an mc_result: MC_OK (0) on success, a negative MC_ERR_ code on
 *   failure (except mc_result_str, which returns a static string). mc_result_str(code)
 *   describes a code; mc_last_error_message gives the detailed message of the calling
 *   thread's last failed call.
 * - Outputs are written only on success: after a failure every output is as it was (the one
 *   exception: *needed with MC_ERR_BUFFER_TOO_SMALL, which reports the size needed).
 * - Every pointer is checked: a NULL where a pointer is required gives MC_ERR_NULL_POINTER.
 *   A non-NULL pointer must be valid for the access described, for the duration of the call.
 *   Pointers documented "may be NULL" are optional outputs.
 * - String outputs take a buffer and its size, (char *buf, size_t len, size_t *needed); when
 *   the string and its NUL do not fit, the call writes only *needed and returns
 *   MC_ERR_BUFFER_TOO_SMALL. buf may be NULL when len is 0, to ask for the size.
 * - Cards are integer handles (mc_card), never pointers. An unknown or closed handle gives
 *   MC_ERR_BAD_HANDLE; closing twice is harmless (the second close returns MC_ERR_BAD_HANDLE).
 *   0 is never a valid handle.
 * - A panic inside the library never crosses into C: it becomes MC_ERR_PANIC.
 * - Every MC_ and mc_ name a comment of this header cites is defined in it (the register
 *   map's own constants that the comments cite, flags and codes of raw commands among them,
 *   come last). MC_ and a CamelCase word (MC_Power, MC_MoveAbsolute) is the name of a PLCopen
 *   function block, not a C name.
 * - Positions, velocities and limits are in user units: counts divided by the axis's scale
 *   (mc_set_scale; default 1, i.e. counts). Time-outs are in milliseconds; on a stepped sim
 *   card (mc_open_sim_stepped) they are in emulated time and waiting advances the card.
 *
 * Threads
 * - Every function may be called from any thread, and handles are safe to use from several
 *   threads at once: commands from different threads on one card are serialised by the
 *   library, each gets its own answer. Moves on one axis follow the axis's state machine
 *   whatever thread sends them (a second move while moving gives MC_ERR_INVALID_STATE).
 * - The last-error message is per thread.
 * - The library starts no thread that calls into the application. An event callback runs
 *   only inside mc_dispatch_events, on the thread that called it.
 *
 * Which calls block
 * - Never block: mc_result_str, mc_last_error_message, mc_version, mc_version_string,
 *   mc_get_info, mc_get_tick, mc_set_scale, mc_events_lost, mc_irq_fd, mc_poll_events,
 *   mc_set_event_callback, mc_axis_settings_default, mc_move_limits_symmetric, mc_sim_time,
 *   mc_group_settings_new, mc_filter_settings_shin_table1, mc_filter_settings_shin_table1_z,
 *   mc_pdplus_settings_die_bonder, mc_set_heartbeat, mc_get_safety_status,
 *   mc_safety_settings_default, mc_sim_options_default, mc_nurbs_clamped_uniform_knots,
 *   mc_filter_settings_all, mc_path_limits_new, mc_nurbs_feed_new, mc_homing_settings_default,
 *   mc_path_settings_uniform, mc_path_segment_line, mc_path_segment_arc,
 *   mc_path_segment_dwell, mc_path_segment_output, mc_get_outputs.
 * - mc_get_status, mc_get_stop_info, mc_group_get_status, mc_group_get_path_settings and
 *   mc_group_path_free do not wait for the card; they retry while the card is rewriting the
 *   status block (well under a microsecond on a running card; after 100 ms of a block that
 *   stays busy, MC_ERR_NOT_RESPONDING).
 * - Block until the card answers the command (microseconds on a running card; at most 2 s,
 *   then MC_ERR_NOT_RESPONDING): mc_enable, mc_disable, mc_configure, mc_move_absolute,
 *   mc_move_relative, mc_halt, mc_stop, mc_release_stop, mc_reset, mc_ping,
 *   mc_set_servo_rate, mc_group_configure, mc_group_enable, mc_group_disable, mc_group_reset,
 *   mc_group_halt, mc_group_stop, mc_group_release_stop, mc_group_move_linear,
 *   mc_group_move_ptp, mc_group_move_circular, mc_axis_set_filters,
 *   mc_axis_configure_pdplus, mc_set_watchdog_timeout, mc_set_estop_input_category, mc_estop,
 *   mc_configure_safety, mc_configure_homing, mc_home, mc_set_position,
 *   mc_group_configure_path, mc_group_path_push, mc_group_path_output, mc_set_outputs,
 *   mc_send_raw.
 *   mc_group_move_nurbs
 *   sends the curve as several commands (a begin, data entries, an end) and blocks until the
 *   card has answered each, as does
 *   mc_group_move_ptp_axes (the axes' limits, one command per three axes, then the move);
 *   mc_reset_faults sends one command, then one MC_Reset per axis in ErrorStop. A move call
 *   returns when the card has accepted it, not when it is done.
 * - mc_group_move_nurbs_path sends its curves one after another and, whenever the group's
 *   queue is full, waits for an earlier piece to finish (up to its timeout for each wait).
 * - mc_group_path_stream sends its items and, whenever the group's path buffer is full, waits
 *   for the running path to make room.
 * - Block up to their timeout: mc_motion_wait, mc_wait_done, mc_group_motion_wait,
 *   mc_group_wait_done, mc_wait_event, mc_dispatch_events.
 * - mc_open, mc_open_sim and mc_open_sim_stepped block until the card has booted (about a
 *   second at most); mc_close blocks while an emulated card's thread stops; mc_sim_step
 *   computes the ticks asked for.
 *
 * Safety: while a card is open the library writes a heartbeat the card's watchdog watches (a
 * thread on a real-time card; once per emulated tick on a stepped sim). If it stops (the
 * process hangs or dies, or mc_set_heartbeat(card, 0)), every axis stops after the watchdog
 * timeout and the trip stays latched (MC_ERR_WATCHDOG_TRIPPED) until mc_reset_faults. Safety
 * stops end in MC_AXIS_STATE_ERROR_STOP with their MC_STOP_REASON_ in mc_status.stop_reason
 * and an MC_EVENT_SAFETY_STOP event. Debugging under gdb or valgrind: set the environment
 * variable MOTIONCARD_SIM_WATCHDOG_MS (milliseconds) and a real-time sim card boots with that
 * watchdog timeout and keeps it as the least mc_set_watchdog_timeout sets (still armed).
 *
 * Event loop: put the descriptor of mc_irq_fd in your poll/epoll set (level-triggered);
 * when it is readable, call mc_dispatch_events(card, 0, &n). Waits in other threads
 * (mc_motion_wait, mc_wait_event) also take the card's interrupts, so also dispatch after
 * them, or with a timeout, rather than relying on the descriptor alone.
 *
 * Language: C89/C90 (ANSI C) and later, and C++98 and later. The header uses no // comments,
 * no bool, no inline code and no enum types (enumerations are uint32_t fields with MC_
 * constants), and compiles with gcc -std=c89 -pedantic-errors -Wall -Wextra -Werror (and
 * -std=gnu89, c99, c11; g++ -std=c++98, c++11). It includes <stddef.h> and <stdint.h>
 * (size_t, int32_t, uint32_t, int64_t, uint64_t), headers C89 does not name: gcc provides
 * <stdint.h> in every -std mode, and glibc declares the 64-bit types as long on 64-bit
 * targets and with __extension__ (long long) on 32-bit ones, so -pedantic-errors accepts them.
 * A C89 toolchain without <stdint.h> must provide these typedefs itself before including
 * this header.
 */

#ifndef MOTIONCARD_H
#define MOTIONCARD_H


/* Generated with cbindgen:0.29.4 */

/* Generated by `cargo xtask codegen` from cffi/src with cbindgen. Do not edit. */

#include <stddef.h>
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif


/**
 * Event kind (`mc_event.kind`). `axis`, `seq`, `code` and `value` are the event's fields;
 * positions and distances in `value` are in user units (the rule of `mc_event`). `MC_EVENT_ACK`
 * and `MC_EVENT_NACK` are taken by the library, never delivered.
 *
 * The command with this seq was accepted.
 */
#define MC_EVENT_ACK 1

/**
 * The command with this seq was refused. code: `MC_NACK_*`.
 */
#define MC_EVENT_NACK 2

/**
 * Value: final actual position.
 */
#define MC_EVENT_MOTION_DONE 3

/**
 * Code: new state, value: old state.
 */
#define MC_EVENT_STATE_CHANGED 4

/**
 * Code: fault bit, value: a measurement.
 */
#define MC_EVENT_FAULT 5

/**
 * Code: reason (a command opcode or fault bit).
 */
#define MC_EVENT_MOTION_ABORTED 6

/**
 * Axis: group; seq: the move; value: 1 when the group is at rest in position.
 */
#define MC_EVENT_GROUP_MOTION_DONE 8

/**
 * Axis: group; code: new state, value: old state.
 */
#define MC_EVENT_GROUP_STATE_CHANGED 9

/**
 * Axis: group; seq: the move; code: the opcode that ended it.
 */
#define MC_EVENT_GROUP_MOTION_ABORTED 10

/**
 * A buffered move started (PLCopen Active). seq: the move; value: its target (velocity mode: its
 * velocity).
 */
#define MC_EVENT_MOTION_ACTIVE 11

/**
 * Velocity mode reached its velocity (PLCopen InVelocity). seq: the command; value: the velocity.
 */
#define MC_EVENT_IN_VELOCITY 12

/**
 * Homing ended without a home point (layout 1.5). seq: the `MC_Home`; code: `MC_HOMING_ERROR_*`;
 * value: the actual position where it failed. Posted once the axis is at rest in Standstill, not
 * homed.
 */
#define MC_EVENT_HOMING_FAILED 13

/**
 * A safety stop began. code: `MC_STOP_REASON_*` reason, value: the measurement (following error,
 * position, heartbeat age s); axis 0xFFFF for the card-wide cause (watchdog, e-stop).
 */
#define MC_EVENT_SAFETY_STOP 16

/**
 * The stopped axis reached rest (and, category 1, its drive was disabled). code:
 * `MC_STOP_REASON_*` reason, value: s since the stop began.
 */
#define MC_EVENT_AT_REST 17

/**
 * The host broke the protocol. code: `MC_PROTO_*`, value: index.
 */
#define MC_EVENT_PROTOCOL_ERROR 18

/**
 * A path segment started (layout 1.6). axis: group; seq: its command; value: its id.
 */
#define MC_EVENT_SEGMENT_START 20

/**
 * A path segment ended (the path left it). As `MC_EVENT_SEGMENT_START`. Both are posted only while
 * more than 4 `*` `MC_GROUP_MAX_AXES` slots of the event ring are free (the room kept for answers
 * and other events), else counted in `events_lost`.
 */
#define MC_EVENT_SEGMENT_END 21

/**
 * The segments queued fell to `group_path.low_water`. axis: group; value: segments queued.
 */
#define MC_EVENT_PATH_LOW_WATER 22

/**
 * The path brakes for the end of what is queued, which is not marked `MC_PATH_LAST`. axis: group;
 * value: the last id queued.
 */
#define MC_EVENT_PATH_STARVED 23

/**
 * A debounced input edge (layout 1.7). axis: the input; code: 1 rising (active), 0 falling; value:
 * the debounced input word.
 */
#define MC_EVENT_INPUT 24

/**
 * A compare channel fired or missed. axis: the channel; seq: its `MC_OP_COMPARE_ARM`; code:
 * `MC_COMPARE_*`; value: the position.
 */
#define MC_EVENT_COMPARE 25

/**
 * A touch probe captured. axis: the channel; seq: its `MC_OP_PROBE_ARM`; code: the capture number
 * since the arm (1, 2, ...); value: the position captured.
 */
#define MC_EVENT_PROBE 26

/**
 * Synchronised motion. axis: the slave; seq: the gear command; code: `MC_SYNC_*`; value: the
 * slave's commanded position (master lost: the master's number).
 */
#define MC_EVENT_SYNC 27

/**
 * A PT/PVT stream. axis: the axis; seq: its `MC_OP_PVT_START`; code: `MC_PVT_EVENT_*`; value: the
 * points queued (low water), the time of the last point run (starved), the last position (done).
 */
#define MC_EVENT_PVT 28

/**
 * The scope (layout 1.8). seq: its `MC_OP_SCOPE_ARM`; code: `MC_SCOPE_EVENT_*`; value: see there.
 */
#define MC_EVENT_SCOPE 29

/**
 * `MC_OP_GROUP_HOME` ended with every member homed (layout 1.11). axis: the group; seq: the
 * command; code: 0; value: the stages run.
 */
#define MC_EVENT_GROUP_HOMED 30

/**
 * `MC_OP_GROUP_HOME` failed as a whole (layout 1.11). axis: the group; seq: the command; code: the
 * failing member's `MC_HOMING_ERROR_*` or `MC_GROUP_HOME_ABORTED`; value: that card axis (-1: the
 * group's own halt, stop or disable).
 */
#define MC_EVENT_GROUP_HOMING_FAILED 31

/**
 * A gantry stopped (layout 1.10). axis: the gantry; code: `MC_STOP_REASON_GANTRY_SKEW` (value: the
 * skew, counts, of the slave beyond the limit) or the `MC_STOP_REASON_*` reason of the member
 * whose safety stop stopped the others (value: that axis).
 */
#define MC_EVENT_GANTRY_FAULT 32

/**
 * `MC_OP_GANTRY_HOME` ended. axis: the gantry; seq: the command; code: 0 squared (value: slave 0's
 * skew, counts) or `MC_HOMING_ERROR_*` (value: the axis that failed).
 */
#define MC_EVENT_GANTRY_HOMED 33

/**
 * An analog input crossed its threshold (layout 1.11). axis: the input; code: 1 above (y >=
 * threshold), 0 below again (y <= threshold - hysteresis); value: the filtered volts y.
 */
#define MC_EVENT_ANALOG 34

/**
 * Layout 1.11: the path came to rest on its pause point. axis: the group; value: the id of the
 * segment it ends (-1: none ran).
 */
#define MC_EVENT_PATH_PAUSED 36

/**
 * Layout 1.12: a sweep ended. axis: its axis; seq: its `MC_OP_FREQ_START`; code: `MC_FREQ_DONE` or
 * `MC_FREQ_ABORTED`; value: the points measured.
 */
#define MC_EVENT_FREQ_DONE 37

/**
 * The card's place on the sync bus changed (layout 1.12). code: `MC_BUSST_LOCKED` (joined) or
 * `MC_BUSST_LOST`; value: the tick.
 */
#define MC_EVENT_SYNC_BUS 38

/**
 * A timed command ran on its tick (layout 1.12). seq: the command; code: its opcode; value: the
 * tick.
 */
#define MC_EVENT_TIMED 39

/**
 * Axis state (`mc_status.state`, the `code` of `MC_EVENT_STATE_CHANGED`): PLCopen's states.
 *
 * Power off.
 */
#define MC_AXIS_STATE_DISABLED 0

/**
 * Powered, at rest, ready for a move.
 */
#define MC_AXIS_STATE_STANDSTILL 1

/**
 * `MC_Home` runs.
 */
#define MC_AXIS_STATE_HOMING 2

/**
 * A point-to-point move.
 */
#define MC_AXIS_STATE_DISCRETE_MOTION 3

/**
 * A velocity move.
 */
#define MC_AXIS_STATE_CONTINUOUS_MOTION 4

/**
 * Coupled to another axis or a group.
 */
#define MC_AXIS_STATE_SYNCHRONIZED_MOTION 5

/**
 * `MC_Stop` in progress or held (until `MC_OP_STOP_RELEASE`).
 */
#define MC_AXIS_STATE_STOPPING 6

/**
 * Stopped by a fault; only `MC_Reset` leaves it.
 */
#define MC_AXIS_STATE_ERROR_STOP 7

/**
 * Group state (`mc_group_status.state`, the `code` of `MC_EVENT_GROUP_STATE_CHANGED`): PLCopen's
 * group states.
 *
 * GroupDisabled.
 */
#define MC_GROUP_STATE_DISABLED 0

/**
 * GroupStandby: enabled, at rest, ready for a move.
 */
#define MC_GROUP_STATE_STANDBY 1

/**
 * GroupMoving: interpolating.
 */
#define MC_GROUP_STATE_MOVING 2

/**
 * GroupHoming: `MC_OP_GROUP_HOME` runs (layout 1.11).
 */
#define MC_GROUP_STATE_HOMING 3

/**
 * GroupStopping: `MC_GroupStop` in progress or held.
 */
#define MC_GROUP_STATE_STOPPING 4

/**
 * GroupErrorStop: stopped by a fault; only `MC_GroupReset` leaves it.
 */
#define MC_GROUP_STATE_ERROR_STOP 5

/**
 * IEC 60204-1 stop category (`mc_estop`, `mc_set_estop_input_category`,
 * `mc_safety_settings.limit_stop`).
 *
 * Remove power now.
 */
#define MC_STOP_CATEGORY_0 0

/**
 * Controlled stop, then remove power.
 */
#define MC_STOP_CATEGORY_1 1

/**
 * Controlled stop, power kept.
 */
#define MC_STOP_CATEGORY_2 2

/**
 * Stop reason (`mc_status.stop_reason`, `mc_stop_info.reason`, the `code` of
 * `MC_EVENT_SAFETY_STOP` and `MC_EVENT_AT_REST`). Safety reasons are `MC_STOP_REASON_WATCHDOG` and
 * above.
 *
 * A motion runs, or none has run.
 */
#define MC_STOP_REASON_NONE 0

/**
 * Reached its target, in position.
 */
#define MC_STOP_REASON_DONE 1

/**
 * `MC_Halt`.
 */
#define MC_STOP_REASON_HALT 2

/**
 * `MC_Stop`.
 */
#define MC_STOP_REASON_STOP 3

/**
 * `MC_Power` off by the host.
 */
#define MC_STOP_REASON_POWER_OFF 4

/**
 * The host closed the card (`MC_OP_HOST_DETACH`): halted.
 */
#define MC_STOP_REASON_HOST_DETACH 5

/**
 * Homing failed (`MC_EVENT_HOMING_FAILED`): stopped, not homed.
 */
#define MC_STOP_REASON_HOMING_FAILED 6

/**
 * A touch probe armed with `MC_PROBE_HALT` captured: halted.
 */
#define MC_STOP_REASON_PROBE 7

/**
 * Another member of its group failed homing (`MC_OP_GROUP_HOME`): halted.
 */
#define MC_STOP_REASON_GROUP_HOMING 8

/**
 * The card lost the sync bus's master (layout 1.12): halted.
 */
#define MC_STOP_REASON_SYNC_LOST 9

/**
 * Host heartbeat lost.
 */
#define MC_STOP_REASON_WATCHDOG 16

/**
 * `MC_OP_ESTOP`.
 */
#define MC_STOP_REASON_ESTOP_COMMAND 17

/**
 * The card's e-stop input.
 */
#define MC_STOP_REASON_ESTOP_INPUT 18

/**
 * The positive limit switch.
 */
#define MC_STOP_REASON_HARD_LIMIT_POS 19

/**
 * The negative limit switch.
 */
#define MC_STOP_REASON_HARD_LIMIT_NEG 20

/**
 * The positive soft limit.
 */
#define MC_STOP_REASON_SOFT_LIMIT_POS 21

/**
 * The negative soft limit.
 */
#define MC_STOP_REASON_SOFT_LIMIT_NEG 22

/**
 * The following error exceeded its limit.
 */
#define MC_STOP_REASON_FOLLOWING_ERROR 23

/**
 * The amplifier's alarm input.
 */
#define MC_STOP_REASON_AMP_ALARM 24

/**
 * The encoder's line-break detector.
 */
#define MC_STOP_REASON_ENCODER_LOSS 25

/**
 * A count change larger than physically possible.
 */
#define MC_STOP_REASON_ENCODER_JUMP 26

/**
 * Queued motion ran out: planned stop at the end of the queue.
 */
#define MC_STOP_REASON_STARVATION 27

/**
 * Command ring indices corrupt.
 */
#define MC_STOP_REASON_CMD_RING 28

/**
 * Event ring indices corrupt.
 */
#define MC_STOP_REASON_EVT_RING 29

/**
 * Another axis of its group tripped.
 */
#define MC_STOP_REASON_GROUP 30

/**
 * A stop did not end within the maximum stop time: power removed.
 */
#define MC_STOP_REASON_STOP_TIMEOUT 31

/**
 * A host attached while the previous host's session was open.
 */
#define MC_STOP_REASON_HOST_CHANGED 32

/**
 * Motion found running with no session attached and armed.
 */
#define MC_STOP_REASON_NO_SESSION 33

/**
 * The gantry's skew exceeded its limit (layout 1.10).
 */
#define MC_STOP_REASON_GANTRY_SKEW 34

/**
 * Another axis of its gantry made a safety stop (layout 1.10).
 */
#define MC_STOP_REASON_GANTRY 35

/**
 * Fault bit of `mc_status.faults` (the `code` of `MC_EVENT_FAULT`).
 *
 * The servo output hit the DAC limit.
 */
#define MC_AXIS_FAULT_DAC_SATURATED 1

/**
 * The host watchdog tripped (the heartbeat stopped).
 */
#define MC_AXIS_FAULT_WATCHDOG 256

/**
 * An e-stop (`MC_OP_ESTOP` or the card's input) stopped the axis.
 */
#define MC_AXIS_FAULT_ESTOP 512

/**
 * At or beyond the positive limit switch.
 */
#define MC_AXIS_FAULT_HARD_LIMIT_POS 1024

/**
 * At or beyond the negative limit switch.
 */
#define MC_AXIS_FAULT_HARD_LIMIT_NEG 2048

/**
 * Beyond the positive soft limit.
 */
#define MC_AXIS_FAULT_SOFT_LIMIT_POS 4096

/**
 * Beyond the negative soft limit.
 */
#define MC_AXIS_FAULT_SOFT_LIMIT_NEG 8192

/**
 * The following error exceeded its limit.
 */
#define MC_AXIS_FAULT_FOLLOWING_ERROR 16384

/**
 * The amplifier's alarm input.
 */
#define MC_AXIS_FAULT_AMP_ALARM 32768

/**
 * Encoder loss or a jump.
 */
#define MC_AXIS_FAULT_ENCODER 65536

/**
 * The host broke the protocol (corrupt ring indices).
 */
#define MC_AXIS_FAULT_PROTOCOL 131072

/**
 * A stop ran past the maximum stop time (layout 1.3).
 */
#define MC_AXIS_FAULT_STOP_TIMEOUT 262144

/**
 * Capability bit of `mc_card_info.capabilities`.
 *
 * S-curve profiles.
 */
#define MC_CARD_CAP_SCURVE 1

/**
 * The FFPIV servo loop.
 */
#define MC_CARD_CAP_FFPIV 2

/**
 * Events raise an interrupt.
 */
#define MC_CARD_CAP_EVENT_IRQ 4

/**
 * Motion bit of `mc_status.raw.motion_flags`.
 *
 * Velocity mode at its (overridden) velocity.
 */
#define MC_MOTION_IN_VELOCITY 1

/**
 * Held still by a 0 % override, in its motion state.
 */
#define MC_MOTION_PAUSED 2

/**
 * The position was set by homing or `MC_SetPosition`.
 */
#define MC_MOTION_HOMED 4

/**
 * The motion running is one that was buffered.
 */
#define MC_MOTION_BUFFERED_ACTIVE 8

/**
 * Layout 1.7 (sync): the slave follows its master (InGear).
 */
#define MC_MOTION_IN_SYNC 256

/**
 * Bit of `mc_status.io`.
 *
 * The positive limit switch input.
 */
#define MC_IO_LIMIT_POS 1

/**
 * The negative limit switch input.
 */
#define MC_IO_LIMIT_NEG 2

/**
 * The home switch input.
 */
#define MC_IO_HOME 4

/**
 * The amplifier alarm input.
 */
#define MC_IO_AMP_ALARM 8

/**
 * The encoder line-break detector.
 */
#define MC_IO_ENCODER_FAULT 16

/**
 * The card's e-stop input, mirrored on every axis.
 */
#define MC_IO_ESTOP 32

/**
 * Output: the amplifier is enabled.
 */
#define MC_IO_DRIVE_ENABLE 256

/**
 * Axes groups on a card (group numbers 0 .. `MC_GROUP_COUNT` - 1).
 */
#define MC_GROUP_COUNT 4

/**
 * Most axes in one group (`mc_group_settings.axes`): as many as the card can have.
 */
#define MC_GROUP_MAX_AXES 8

/**
 * Acc/dec mode (`mc_group_settings.accdec`).
 *
 * S-curve of the tangential feed along the path.
 */
#define MC_GROUP_ACCDEC_PRE 1

/**
 * Per-axis acc/dec filters after interpolation.
 */
#define MC_GROUP_ACCDEC_POST 2

/**
 * Arc interpolator (`mc_group_settings.interpolator`).
 *
 * Points exactly on the circle.
 */
#define MC_GROUP_INTERP_EXACT 0

/**
 * Kim eq 15-23 for arcs (constant feed: needs `MC_GROUP_ACCDEC_POST` only).
 */
#define MC_GROUP_INTERP_REFERENCE_WORD 1

/**
 * Plane of an arc (`mc_group_move_circular`, path arcs).
 *
 * Group axes 0, 1.
 */
#define MC_ARC_PLANE_XY 0

/**
 * Group axes 1, 2.
 */
#define MC_ARC_PLANE_YZ 1

/**
 * Group axes 2, 0.
 */
#define MC_ARC_PLANE_ZX 2

/**
 * Any two group axes u, v, named apart (layout 1.10).
 */
#define MC_ARC_PLANE_AXES 3

/**
 * How an arc is given (`mc_arc.mode`): `aux` and `end` are in the coordinates of its plane.
 *
 * Aux = centre.
 */
#define MC_ARC_BY_CENTRE 0

/**
 * `aux_u` = radius (negative: the arc longer than half a turn).
 */
#define MC_ARC_BY_RADIUS 1

/**
 * Aux = a point on the arc (three-point circle).
 */
#define MC_ARC_BY_BORDER 2

/**
 * Acc/dec filter kind (`mc_filter.kind`).
 *
 * Pass-through.
 */
#define MC_FILTER_KIND_NONE 0

/**
 * Moving average (linear acc/dec; Kim eq 1).
 */
#define MC_FILTER_KIND_LINEAR 1

/**
 * First order (exponential acc/dec; Kim eq 7-9).
 */
#define MC_FILTER_KIND_EXPONENTIAL 2

/**
 * Linear followed by exponential (bell-shaped; Shin eq 40).
 */
#define MC_FILTER_KIND_BELL 3

/**
 * Bit of `mc_homing_settings.flags`.
 *
 * The encoder has an index channel (index methods need it).
 */
#define MC_HOMING_FLAG_INDEX 1

/**
 * End at the home point.
 */
#define MC_HOMING_FLAG_MOVE_TO_HOME 2

/**
 * Why homing failed: the `code` of `MC_EVENT_HOMING_FAILED`.
 *
 * A limit switch the method did not reverse at: the switch is missing.
 */
#define MC_HOMING_ERROR_LIMIT 1

/**
 * `max_distance` from the start without the switch or hard stop.
 */
#define MC_HOMING_ERROR_DISTANCE 2

/**
 * Not homed within the timeout.
 */
#define MC_HOMING_ERROR_TIMEOUT 3

/**
 * No index pulse within `index_distance`.
 */
#define MC_HOMING_ERROR_NO_INDEX 4

/**
 * A motion of the method could not be planned.
 */
#define MC_HOMING_ERROR_PLAN 5

/**
 * `flags` of `mc_set_position`: the position moves by the argument (else it becomes the argument).
 */
#define MC_SET_POSITION_RELATIVE 1

/**
 * Segments in a group's path buffer.
 */
#define MC_PATH_SEGMENTS 4096

/**
 * The card's digital outputs (card.outputs).
 */
#define MC_CARD_OUTPUTS 16

/**
 * `mc_path_segment.buffer` (PLCopen BufferMode): how a segment joins the one before it.
 *
 * The path stops along its geometry within its limits, the rest is aborted, and this segment
 * starts from there.
 */
#define MC_PATH_BUFFER_ABORTING 0

/**
 * Exact stop at the corner, then this segment.
 */
#define MC_PATH_BUFFER_BUFFERED 1

/**
 * Blend; corner speed <= the lower of the two feeds.
 */
#define MC_PATH_BUFFER_BLEND_LOW 2

/**
 * Blend; corner speed <= the previous segment's feed.
 */
#define MC_PATH_BUFFER_BLEND_PREVIOUS 3

/**
 * Blend; corner speed <= this segment's feed.
 */
#define MC_PATH_BUFFER_BLEND_NEXT 4

/**
 * Blend; corner speed <= the higher of the two feeds.
 */
#define MC_PATH_BUFFER_BLEND_HIGH 5

/**
 * `mc_path_segment.transition` (PLCopen TransitionMode): how a blend is made. `tolerance` is in
 * user units of the first group axis.
 *
 * No blend: an exact stop at the corner.
 */
#define MC_PATH_TRANSITION_NONE 0

/**
 * The blend keeps within `tolerance` counts of the corner.
 */
#define MC_PATH_TRANSITION_MAX_DEVIATION 1

/**
 * The blend begins `tolerance` counts before the corner.
 */
#define MC_PATH_TRANSITION_CORNER_DISTANCE 2

/**
 * Thinh's blending of two lines: each runs as its own rest-to-rest S-curve, this one starting
 * while the one before decelerates, within `tolerance` counts of the corner; refused
 * (`MC_NACK_PATH_MODE`) on or after an arc, and a blend after such a line is refused too.
 */
#define MC_PATH_TRANSITION_TIME_SHIFT 3

/**
 * When an output action fires (`mc_path_segment.at`, `mc_group_path_output`); `distance` is in
 * user units of the first group axis.
 *
 * As the segment starts.
 */
#define MC_OUTPUT_AT_START 0

/**
 * As the segment ends.
 */
#define MC_OUTPUT_AT_END 1

/**
 * Once the segment has run `distance` counts.
 */
#define MC_OUTPUT_AT_DISTANCE 2

/**
 * Bit of `mc_group_status.path_flags`.
 *
 * A segment is running (`path_id` is valid).
 */
#define MC_PATH_STATUS_RUNNING 1

/**
 * Braking for the end of what is queued.
 */
#define MC_PATH_STATUS_STARVING 2

/**
 * A halt or stop runs along the path.
 */
#define MC_PATH_STATUS_HALTING 4

/**
 * Layout 1.11: braking for the pause point (`MC_OP_PATH_PAUSE`).
 */
#define MC_PATH_STATUS_PAUSING 8

/**
 * At rest on the pause point (`path_id`: the segment it ends).
 */
#define MC_PATH_STATUS_PAUSED 16

/**
 * The card's digital inputs (card.inputs).
 */
#define MC_CARD_INPUTS 16

/**
 * Compare channels of the card.
 */
#define MC_COMPARE_CHANNELS 4

/**
 * Positions queued per compare channel.
 */
#define MC_COMPARE_TABLE_LEN 4096

/**
 * Touch-probe channels of the card.
 */
#define MC_PROBE_CHANNELS 4

/**
 * The length of `mc_probe_info.positions`.
 *
 * Captures kept in `probe_status` (a ring).
 */
#define MC_PROBE_QUEUE 8

/**
 * The `code` of `MC_EVENT_COMPARE`.
 *
 * A position fired.
 */
#define MC_COMPARE_FIRED 1

/**
 * A position missed: passed when it became the next one, or inside the pulse before it.
 */
#define MC_COMPARE_MISSED 2

/**
 * The table's queue fell to `low_water`; value: queued.
 */
#define MC_COMPARE_LOW_WATER 3

/**
 * `state` of a compare channel or a touch probe (`mc_compare_info.state`, `mc_probe_info.state`).
 *
 * Not armed.
 */
#define MC_IO_STATE_IDLE 0

/**
 * Armed: watching or capturing.
 */
#define MC_IO_STATE_ARMED 1

/**
 * A single compare or series fired (or missed) all; a single-shot probe captured.
 */
#define MC_IO_STATE_DONE 2

/**
 * `mc_probe_trigger.input` that is not an input.
 *
 * Probe input: the axis's encoder index pulse.
 */
#define MC_PROBE_INPUT_INDEX 16

/**
 * Bit of `mc_probe_trigger.edges` (one or both).
 *
 * Capture as the input becomes active.
 */
#define MC_PROBE_EDGE_RISING 1

/**
 * Capture as the input becomes inactive.
 */
#define MC_PROBE_EDGE_FALLING 2

/**
 * What a slave follows (`master_kind` of `mc_gear_in`, `mc_gear_in_pos`, `mc_cam_in`).
 *
 * Flags: the master axis's commanded position.
 */
#define MC_MASTER_COMMANDED 0

/**
 * The master axis's actual position (its encoder).
 */
#define MC_MASTER_ACTUAL 1

/**
 * An auxiliary encoder input (`0..MC_AUX_ENCODERS-1`).
 */
#define MC_MASTER_AUX 2

/**
 * The master axis's actual position led by one servo period (encoder + v x Ts, v its velocity
 * estimate), in 1/65536 count: no tick of lag at a constant velocity (layout 1.9).
 */
#define MC_MASTER_ACTUAL_LEAD 3

/**
 * Auxiliary encoder inputs of the card (conveyor, handwheel).
 */
#define MC_AUX_ENCODERS 2

/**
 * The `code` of `MC_EVENT_SYNC`.
 *
 * `MC_GearIn` caught up: the slave follows the ratio (InGear).
 */
#define MC_SYNC_IN_GEAR 1

/**
 * `MC_GearInPos` reached its sync point (InSync).
 */
#define MC_SYNC_IN_SYNC 2

/**
 * The master is disabled or in ErrorStop: the slave stops.
 */
#define MC_SYNC_MASTER_LOST 3

/**
 * `MC_EVENT_SYNC`: a cam that is not periodic passed its table's end.
 */
#define MC_SYNC_CAM_END 4

/**
 * `MC_EVENT_SYNC`: the table switched at the end of a cycle (seq: the `MC_OP_CAM_IN` that asked
 * for it).
 */
#define MC_SYNC_CAM_SWITCH 5

/**
 * Points buffered per axis.
 */
#define MC_PVT_LEN 4096

/**
 * The `code` of `MC_EVENT_PVT`.
 *
 * The points queued fell to the stream's low water.
 */
#define MC_PVT_EVENT_LOW_WATER 1

/**
 * The stream ran dry before a last point: the axis stops on its stop ramp (Stopping, then
 * Standstill; `MC_EVENT_MOTION_ABORTED`).
 */
#define MC_PVT_EVENT_STARVED 2

/**
 * The last point was reached (motion done follows in position).
 */
#define MC_PVT_EVENT_DONE 3

/**
 * Bit of the `flags` of `mc_cam_load_table`.
 *
 * A cubic spline: velocity and acceleration continuous (else linear).
 */
#define MC_CAM_CUBIC 1

/**
 * Periodic: the master's period is the table's span.
 */
#define MC_CAM_PERIODIC 2

/**
 * Cam tables the card holds.
 */
#define MC_CAM_TABLES 4

/**
 * Points of a cam table, at most.
 */
#define MC_CAM_MAX_POINTS 1024

/**
 * `mc_axis_settings.servo_law`: the servo law an axis runs.
 */
#define MC_SERVO_FFPIV 0

/**
 * Yeh eq 2.12 with the gains and drive model of `axis_pdplus[axis]`.
 */
#define MC_SERVO_PDPLUS 1

/**
 * Layout 1.11: PID on the following error with velocity, acceleration and Coulomb friction
 * feed-forward (Kim section 5), the gains of `axis_pidff[axis]`.
 */
#define MC_SERVO_PIDFF 2

/**
 * Servo filters per axis (slots 0..`MC_BIQUADS`-1).
 *
 * Filters per axis.
 */
#define MC_BIQUADS 4

/**
 * `mc_servo_filter.kind`: what a servo filter is.
 *
 * The slot is empty.
 */
#define MC_BIQUAD_NONE 0

/**
 * `freq_hz`: centre; damping: the poles' damping ratio (the width: the -3 dB band is about 2
 * damping `freq_hz` wide); `depth_db`: the gain at the centre, dB (-120..0).
 */
#define MC_BIQUAD_NOTCH 1

/**
 * Second order: `freq_hz`: corner; damping: damping ratio (0.707: Butterworth).
 */
#define MC_BIQUAD_LOWPASS 2

/**
 * First order (1 + s/w1) / (1 + s/w2): `freq_hz`: the zero's w1/2pi; `freq2_hz`: the pole's w2/2pi
 * (above `freq_hz`: a lead, below: a lag); DC gain 1.
 */
#define MC_BIQUAD_LEAD_LAG 3

/**
 * The coefficients as given: y = b0 x + b1 `x[-1]` + b2 `x[-2]` - a1 `y[-1]` - a2 `y[-2]`.
 */
#define MC_BIQUAD_RAW 4

/**
 * Channels per sample, at most (`mc_scope_settings.n_channels`).
 */
#define MC_SCOPE_CHANNELS 16

/**
 * Samples in the scope ring (a power of two).
 */
#define MC_SCOPE_RING_LEN 4096

/**
 * Scope signal: `mc_scope_settings.source[k]` is `MC_SCOPE_SIG_*` | index << 16. Axis signals
 * (1..18; index: the axis) are the axis status's values of the tick, group signals (32..34; index:
 * the group) the group status's, card signals (48..50; index 0) the card's words.
 *
 * Commanded position, counts (`cmd_pos`).
 */
#define MC_SCOPE_SIG_CMD_POS 1

/**
 * Commanded velocity, counts/s (`cmd_vel`).
 */
#define MC_SCOPE_SIG_CMD_VEL 2

/**
 * Commanded acceleration, counts/s^2 (`cmd_acc`).
 */
#define MC_SCOPE_SIG_CMD_ACC 3

/**
 * Actual position, counts (`act_pos`).
 */
#define MC_SCOPE_SIG_ACT_POS 4

/**
 * Actual velocity, filtered, counts/s (`act_vel`).
 */
#define MC_SCOPE_SIG_ACT_VEL 5

/**
 * Following error, counts (ferr).
 */
#define MC_SCOPE_SIG_FERR 6

/**
 * DAC output, V (`dac_v`).
 */
#define MC_SCOPE_SIG_DAC 7

/**
 * The servo law's output before the DAC clamp, V (`u_request`).
 */
#define MC_SCOPE_SIG_U_REQUEST 8

/**
 * The raw encoder count (encoder).
 */
#define MC_SCOPE_SIG_ENCODER 9

/**
 * The proportional term, V.
 */
#define MC_SCOPE_SIG_SERVO_P 10

/**
 * The integral term, V.
 */
#define MC_SCOPE_SIG_SERVO_I 11

/**
 * The velocity feedback (FFPIV) or derivative (PD+) term, V.
 */
#define MC_SCOPE_SIG_SERVO_D 12

/**
 * The feed-forward terms, V.
 */
#define MC_SCOPE_SIG_SERVO_FF 13

/**
 * Layout 1.10: the skew of a gantry's slave (index: the slave), counts; 0 for an axis that is no
 * gantry's slave.
 */
#define MC_SCOPE_SIG_GANTRY_SKEW 14

/**
 * Layout 1.10: the compensated position, the motor's reference, counts (`comp_pos`: `cmd_pos` plus
 * the pitch-error and backlash correction).
 */
#define MC_SCOPE_SIG_COMP_POS 15

/**
 * Layout 1.11: the servo law's output, the biquad chain's input, V.
 */
#define MC_SCOPE_SIG_FILTER_IN 16

/**
 * Layout 1.11: the biquad chain's output before the DAC clamp, V (`u_request`; the law's output
 * when no filter is set).
 */
#define MC_SCOPE_SIG_FILTER_OUT 17

/**
 * Layout 1.11: PID+FF's Coulomb friction feed-forward, V (part of `MC_SCOPE_SIG_SERVO_FF`; 0 under
 * the other laws).
 */
#define MC_SCOPE_SIG_SERVO_FRICTION 18

/**
 * Layout 1.12: the sweep's sine of the tick on this axis, counts (`MC_FREQ_REF`) or V
 * (`MC_FREQ_OUTPUT`); 0 with no sweep.
 */
#define MC_SCOPE_SIG_FREQ_INJECT 19

/**
 * Layout 1.12: the frequency the sweep runs on this axis, Hz (0: none).
 */
#define MC_SCOPE_SIG_FREQ_HZ 20

/**
 * Tangential velocity before the filters, counts/s (feed).
 */
#define MC_SCOPE_SIG_PATH_SPEED 32

/**
 * Tangential acceleration, counts/s^2 (`feed_acc`).
 */
#define MC_SCOPE_SIG_PATH_ACC 33

/**
 * Distance along the active move, counts (`path_pos`).
 */
#define MC_SCOPE_SIG_PATH_POS 34

/**
 * The debounced digital inputs, bit i = input i (card.inputs).
 */
#define MC_SCOPE_SIG_INPUTS 48

/**
 * The digital outputs (card.outputs).
 */
#define MC_SCOPE_SIG_OUTPUTS 49

/**
 * The inputs as sampled (`card.inputs_raw`).
 */
#define MC_SCOPE_SIG_INPUTS_RAW 50

/**
 * Layout 1.11: analog input 0, filtered, V (`analog_status.input[0]`).
 */
#define MC_SCOPE_SIG_AIN0 51

/**
 * Analog input 1, filtered, V.
 */
#define MC_SCOPE_SIG_AIN1 52

/**
 * Analog input 2, filtered, V.
 */
#define MC_SCOPE_SIG_AIN2 53

/**
 * Analog input 3, filtered, V.
 */
#define MC_SCOPE_SIG_AIN3 54

/**
 * Analog input 4, filtered, V.
 */
#define MC_SCOPE_SIG_AIN4 55

/**
 * Analog input 5, filtered, V.
 */
#define MC_SCOPE_SIG_AIN5 56

/**
 * Analog input 6, filtered, V.
 */
#define MC_SCOPE_SIG_AIN6 57

/**
 * Analog input 7, filtered, V.
 */
#define MC_SCOPE_SIG_AIN7 58

/**
 * Spare DAC output 0, V (`analog_status.output[0]`).
 */
#define MC_SCOPE_SIG_AOUT0 59

/**
 * Spare DAC output 1, V.
 */
#define MC_SCOPE_SIG_AOUT1 60

/**
 * Spare DAC output 2, V.
 */
#define MC_SCOPE_SIG_AOUT2 61

/**
 * Spare DAC output 3, V.
 */
#define MC_SCOPE_SIG_AOUT3 62

/**
 * The PSO's output, V or duty 0..1 (`analog_status.pso_value`).
 */
#define MC_SCOPE_SIG_PSO 63

/**
 * `mc_scope_settings.mode`.
 *
 * `post_trigger` samples from the trigger sample on, then done.
 */
#define MC_SCOPE_ONE_SHOT 0

/**
 * Until `MC_OP_SCOPE_STOP`.
 */
#define MC_SCOPE_CONTINUOUS 1

/**
 * `mc_scope_settings.trigger`: when the capture starts.
 *
 * The first sample after the arm.
 */
#define MC_SCOPE_TRIG_IMMEDIATE 0

/**
 * The first sample after an `MC_OP_SCOPE_TRIGGER`.
 */
#define MC_SCOPE_TRIG_COMMAND 1

/**
 * Channel `trigger_channel` crosses level.
 */
#define MC_SCOPE_TRIG_LEVEL 2

/**
 * An edge of debounced input `trigger_input`.
 */
#define MC_SCOPE_TRIG_INPUT 3

/**
 * A safety fault bit of an axis appears.
 */
#define MC_SCOPE_TRIG_FAULT 4

/**
 * `mc_scope_settings.edge`: which way a level or input trigger fires.
 *
 * Previous < level <= this one; an input becoming active.
 */
#define MC_SCOPE_RISING 0

/**
 * Previous > level >= this one; an input becoming inactive.
 */
#define MC_SCOPE_FALLING 1

/**
 * Either way.
 */
#define MC_SCOPE_EITHER 2

/**
 * `mc_scope_info.state`.
 *
 * Not sampling.
 */
#define MC_SCOPE_STATE_IDLE 0

/**
 * Armed: sampling into the history, waiting for the trigger.
 */
#define MC_SCOPE_STATE_WAITING 1

/**
 * Triggered: samples go to the ring.
 */
#define MC_SCOPE_STATE_CAPTURING 2

/**
 * A one-shot capture ended.
 */
#define MC_SCOPE_STATE_DONE 3

/**
 * The `code` of `MC_EVENT_SCOPE`.
 *
 * Value: the trigger sample's tick.
 */
#define MC_SCOPE_EVENT_TRIGGERED 1

/**
 * A one-shot capture ended; value: the samples it put in the ring or lost (pre-trigger +
 * `post_trigger`).
 */
#define MC_SCOPE_EVENT_DONE 2

/**
 * A sample found the ring full; value: `scope_status.lost`.
 */
#define MC_SCOPE_EVENT_LOST 3

/**
 * Opcode of a raw command (`mc_send_raw`).
 *
 * Does nothing but answer: the round-trip probe.
 */
#define MC_OP_NOP 1

/**
 * `MC_Power` Enable=TRUE.
 */
#define MC_OP_POWER_ON 2

/**
 * `MC_Power` Enable=FALSE.
 */
#define MC_OP_POWER_OFF 3

/**
 * Args: target, vmax, amax, dmax, j1, j3, j5, j7. flags: `MC_MOVE_BUFFERED`, a direction (layout
 * 1.10: `MC_MOVE_DIR_*`, modulo axes only).
 */
#define MC_OP_MOVE_ABSOLUTE 4

/**
 * Args: distance (from the commanded position), then as `MOVE_ABSOLUTE`.
 */
#define MC_OP_MOVE_RELATIVE 5

/**
 * Args: dmax, jerk. Decelerate, then Standstill.
 */
#define MC_OP_HALT 6

/**
 * Args: dmax, jerk. Decelerate, stay in Stopping.
 */
#define MC_OP_STOP 7

/**
 * Leave Stopping once at rest (`MC_Stop` Execute=FALSE).
 */
#define MC_OP_STOP_RELEASE 8

/**
 * `MC_Reset`: ErrorStop -> Standstill or Disabled.
 */
#define MC_OP_RESET 9

/**
 * Copy and validate `axis_config[axis]`.
 */
#define MC_OP_APPLY_AXIS_CONFIG 10

/**
 * Copy and validate `card_config` (axis field ignored).
 */
#define MC_OP_APPLY_CARD_CONFIG 11

/**
 * Args: distance (from the target of the last move), then as `MOVE_ABSOLUTE`.
 */
#define MC_OP_MOVE_ADDITIVE 12

/**
 * `MC_MoveVelocity`: args: velocity (signed), amax, dmax, jerk. ContinuousMotion;
 * `MC_EVENT_IN_VELOCITY` once at the velocity. Aborting.
 */
#define MC_OP_MOVE_VELOCITY 13

/**
 * Velocity mode with the jog feed: args: velocity (signed, |v| <= `axis_config.jog_max_vel`, else
 * `MC_NACK_OUT_OF_RANGE`) at the axis's `jog_accel` and `jog_jerk`. Releasing the button is
 * `MC_OP_HALT`.
 */
#define MC_OP_JOG 14

/**
 * `MC_SetOverride`: args: velocity factor `0..MC_OVERRIDE_MAX` (else `MC_NACK_OVERRIDE_RANGE`).
 * Scales the axis's velocity limit (moves) or velocity (velocity mode); the change is planned from
 * the current state within the acceleration and jerk limits. 0 holds the axis still in its motion
 * state; a factor > 0 resumes from there.
 */
#define MC_OP_SET_OVERRIDE 15

/**
 * Copy and validate `group_config[group]` (group disabled).
 */
#define MC_OP_GROUP_CONFIGURE 16

/**
 * Copy and validate `axis_filter[axis]`.
 */
#define MC_OP_APPLY_AXIS_FILTER 17

/**
 * `MC_GroupEnable`.
 */
#define MC_OP_GROUP_ENABLE 18

/**
 * `MC_GroupDisable`.
 */
#define MC_OP_GROUP_DISABLE 19

/**
 * `MC_GroupStop`: args: dmax, jerk (along the path).
 */
#define MC_OP_GROUP_STOP 20

/**
 * Leave GroupStopping once at rest (`MC_GroupStop` Execute=FALSE).
 */
#define MC_OP_GROUP_STOP_RELEASE 21

/**
 * `MC_GroupReset`.
 */
#define MC_OP_GROUP_RESET 22

/**
 * `MC_GroupHalt`: args: dmax, jerk.
 */
#define MC_OP_GROUP_HALT 23

/**
 * `MC_MoveLinear*`: args: v, a, d, j, then one target per group axis.
 */
#define MC_OP_GROUP_MOVE_LINEAR 24

/**
 * `MC_MoveCircular*`: args: v, a, d, j, `end_u`, `end_v`, `aux_u`, `aux_v`, then the helical
 * targets of the group's other axes, in group order.
 */
#define MC_OP_GROUP_MOVE_CIRCULAR 25

/**
 * Synchronised point-to-point (Kim eq 10-14): args: v, a, d, j (per axis), then one target per
 * group axis. Flag `MC_PTP_AXIS_LIMITS`: each axis also within the limits staged for it (the
 * smaller wins).
 */
#define MC_OP_GROUP_MOVE_PTP 26

/**
 * Args: degree, `n_ctrl`, `n_knots`, feed, accel, jerk, chord tolerance, saturation budget (0..1]
 * ; flags: `MC_MOVE_BUFFERED`, `MC_NURBS_SATURATION`.
 */
#define MC_OP_NURBS_BEGIN 27

/**
 * Args: offset into the stream, count (1..12), then count values.
 */
#define MC_OP_NURBS_DATA 28

/**
 * Validate the curve and queue the move.
 */
#define MC_OP_NURBS_END 29

/**
 * Stage per-axis limits for the next `MC_OP_GROUP_MOVE_PTP` (above).
 */
#define MC_OP_GROUP_PTP_LIMITS 30

/**
 * `MC_SetOverride` of a group (above).
 */
#define MC_OP_GROUP_SET_OVERRIDE 31

/**
 * Copy and validate safety (axis field ignored).
 */
#define MC_OP_APPLY_SAFETY_CONFIG 32

/**
 * Copy and validate `axis_safety[axis]`.
 */
#define MC_OP_APPLY_AXIS_SAFETY 33

/**
 * Args: category (0, 1 or 2). Every axis; latched.
 */
#define MC_OP_ESTOP 34

/**
 * Clear the card-wide latches (watchdog, e-stop) once their causes are gone; axes then leave
 * ErrorStop by `MC_OP_RESET`.
 */
#define MC_OP_SAFETY_RESET 35

/**
 * Flags: the new session id (nonzero). If another session is still attached (its host died or hung
 * without detaching), every enabled axis makes a category 1 stop with reason
 * `MC_STOP_REASON_HOST_CHANGED`: a new host never inherits motion it did not start. The ack's
 * value is the number of axes that stop made. The attach arms the watchdog: its heartbeat must
 * come within the watchdog timeout.
 */
#define MC_OP_HOST_ATTACH 36

/**
 * Flags: the session id. A clean close: every moving axis and group halts along its axis stop ramp
 * (reason `MC_STOP_REASON_HOST_DETACH`, no fault latched) and the watchdog is disarmed until the
 * next attach (later heartbeats do not arm it); until then the session gate refuses motion
 * (`MC_NACK_NO_SESSION`). `MC_NACK_SESSION` if another session is attached.
 */
#define MC_OP_HOST_DETACH 37

/**
 * Copy and validate `axis_homing[axis]`.
 */
#define MC_OP_APPLY_AXIS_HOMING 48

/**
 * `MC_Home`: args: position (what the home point reads, before the home offset). From Standstill.
 */
#define MC_OP_HOME 49

/**
 * `MC_SetPosition`: args: position; flags: `MC_SET_POSITION_RELATIVE`. The actual and commanded
 * positions become position (relative: move by it) without moving; sets `MC_MOTION_HOMED`.
 * Standstill or Disabled.
 */
#define MC_OP_SET_POSITION 50

/**
 * Args: id, feed, tolerance, then one target per group axis. flags: `MC_MOVE_RELATIVE`,
 * `MC_PATH_*`.
 */
#define MC_OP_PATH_LINE 56

/**
 * Args: id, feed, tolerance, `end_u`, `end_v`, `aux_u`, `aux_v` (as `MC_OP_GROUP_MOVE_CIRCULAR`),
 * then the targets of the other group axes in order (a helix). flags: `MC_MOVE_RELATIVE`,
 * `MC_CIRC_*`, `MC_PATH_*`.
 */
#define MC_OP_PATH_ARC 57

/**
 * Args: id, seconds (0 < t <= `MC_MAX_MOVE_TIME`): an exact stop, then a wait. flags:
 * `MC_PATH_LAST`.
 */
#define MC_OP_PATH_DWELL 58

/**
 * Args: output (`0..MC_CARD_OUTPUTS-1`), on (0 or 1), distance. flags: `MC_OUTPUT_AT_*`. Sets or clears
 * the output when the next motion segment queued starts, ends, or has run `distance` counts; at
 * most `MC_PATH_OUTPUTS_PENDING` before that segment.
 */
#define MC_OP_PATH_OUTPUT 59

/**
 * Copy and validate `group_path[group]` (path empty and at rest).
 */
#define MC_OP_APPLY_GROUP_PATH 60

/**
 * Args: mask, value (`0..2^MC_CARD_OUTPUTS-1`): set the outputs in mask to value now (axis field
 * ignored).
 */
#define MC_OP_SET_OUTPUTS 61

/**
 * A NURBS curve as one path segment: args: id, feed, tolerance, degree, `n_ctrl`, `n_knots`, fit
 * tolerance (> 0: the largest distance of the commanded path from the curve, counts). flags:
 * `MC_MOVE_RELATIVE` (control points from the path's end), `MC_PATH_*` (a time-shifted transition
 * is refused). The curve follows in `MC_OP_NURBS_DATA` entries and is queued by `MC_OP_NURBS_END`,
 * as a NURBS move; it must start within the fit tolerance of the path's end
 * (`MC_NACK_NURBS_START`). On the card it takes one buffer entry per piece: quintics fitted to the
 * curve, curvature-continuous where it is (`MC_NACK_QUEUE_FULL` until they fit;
 * `MC_NACK_PATH_CURVE`).
 */
#define MC_OP_PATH_NURBS 62

/**
 * Copy and validate `io_config` (axis field ignored).
 */
#define MC_OP_APPLY_IO_CONFIG 64

/**
 * Axis: the axis watched. args: channel, output (`0..MC_CARD_OUTPUTS-1`), `pulse_us`, `low_water`
 * (table: the `MC_EVENT_COMPARE` low-water mark, 0: none), position (single) or start (series),
 * pitch (series, counts, >= 1), count (series, 1..2^31-1). flags: `MC_CMP_MODE_*` and
 * `MC_CMP_DIR_*`. `MC_NACK_COMPARE_BUSY` if the channel is armed (a channel done may be armed
 * again) or another armed channel pulses that output. A table channel fires what was queued before
 * (`MC_OP_COMPARE_TABLE`) and what is queued after; its queue is kept from one arm to the next
 * until `MC_OP_COMPARE_DISARM`.
 */
#define MC_OP_COMPARE_ARM 65

/**
 * Args: channel, n (`1..MC_COMPARE_TABLE_MAX`), then n positions (strictly beyond the last queued
 * in the direction, else `MC_NACK_COMPARE_ORDER`; no room: `MC_NACK_COMPARE_FULL`, none taken).
 * flags: `MC_CMP_DIR_POS` or `_NEG` (the table's; the arm must agree). Ack value: the free room
 * after.
 */
#define MC_OP_COMPARE_TABLE 66

/**
 * Args: channel. Stops the channel, drops its table, ends its pulse.
 */
#define MC_OP_COMPARE_DISARM 67

/**
 * `MC_TouchProbe`. axis: the axis captured. args: channel, input (`0..MC_CARD_INPUTS-1` or
 * `MC_PROBE_INPUT_INDEX`), `window_lo`, `window_hi`. flags: `MC_PROBE_EDGE_RISING` / `_FALLING`
 * (one or both), `MC_PROBE_CONTINUOUS`, `MC_PROBE_WINDOW`. Re-arming restarts the channel.
 */
#define MC_OP_PROBE_ARM 68

/**
 * `MC_AbortTrigger`. args: channel.
 */
#define MC_OP_PROBE_ABORT 69

/**
 * Args: master, numerator, denominator, vmax, amax, jerk. flags: `MC_MASTER_*`. Aborting; from
 * Standstill, DiscreteMotion, ContinuousMotion or SynchronizedMotion (a new ratio). The ack's
 * value (and `MC_OP_GEAR_IN_POS's`): the coupling's offset, slave counts with the master at 0 (in
 * gear: slave = offset + ratio x master, counts; anchored where both were at the engagement, or at
 * the sync point).
 */
#define MC_OP_GEAR_IN 80

/**
 * As `MC_OP_GEAR_IN`, then args: master sync position, slave sync position: the slave reaches the
 * slave position exactly when the master reaches the master position, along a quintic in the
 * master's position (velocity and acceleration continuous), checked against vmax, amax, jerk at
 * the master's present velocity (else `MC_NACK_INFEASIBLE`; a master at rest or moving away: the
 * same).
 */
#define MC_OP_GEAR_IN_POS 81

/**
 * `MC_GearOut`: the slave leaves the coupling in velocity mode at its velocity (ContinuousMotion,
 * `MC_EVENT_IN_VELOCITY` with this command's seq), its acceleration ramped to 0 within the gear's
 * amax and jerk; stop it with `MC_OP_HALT`. The gear command: `MC_EVENT_MOTION_ABORTED` (code
 * `MC_OP_GEAR_OUT`).
 */
#define MC_OP_GEAR_OUT 82

/**
 * Args: vmax, amax, low water (points, 0: none). flags: `MC_PVT_PT`. Standstill, no stream running
 * (else `MC_NACK_PVT_SEQUENCE`).
 */
#define MC_OP_PVT_BEGIN 83

/**
 * Args: count (`1..MC_PVT_POINTS_MAX`), then time, position, velocity of each (PT: velocity
 * ignored). flags: `MC_PVT_LAST` (the last of these is the stream's last). Ack value: the points
 * still free.
 */
#define MC_OP_PVT_POINTS 84

/**
 * Args: axis mask (bit i: axis i; 0: this axis): the streams of every axis in it start on the same
 * tick.
 */
#define MC_OP_PVT_START 85

/**
 * Args: table, points (`2..MC_CAM_MAX_POINTS`; cubic: 3..). flags: `MC_CAM_CUBIC`,
 * `MC_CAM_PERIODIC`. Any axis.
 */
#define MC_OP_CAM_TABLE 86

/**
 * Args: table, index of the first point, count (`1..MC_CAM_DATA_MAX`), then master, slave of each.
 */
#define MC_OP_CAM_DATA 87

/**
 * Args: master, table, master offset, slave offset, master scale, slave scale, vmax, amax, jerk.
 * flags: `MC_MASTER_*` | `MC_CAM_AT_CYCLE_END`.
 */
#define MC_OP_CAM_IN 88

/**
 * As `MC_OP_GEAR_OUT`.
 */
#define MC_OP_CAM_OUT 89

/**
 * Validate and copy `scope_config` (axis field ignored).
 */
#define MC_OP_SCOPE_CONFIGURE 90

/**
 * Start sampling and wait for the trigger (scope idle or done).
 */
#define MC_OP_SCOPE_ARM 91

/**
 * Trigger at the next sample (the scope waits for a trigger).
 */
#define MC_OP_SCOPE_TRIGGER 92

/**
 * Stop sampling: the scope is idle (armed, waiting or done).
 */
#define MC_OP_SCOPE_STOP 93

/**
 * Args: block kind (`MC_CONFIG_*`), index (axis or group; 0 for the card-wide blocks). A kind the
 * card does not know, or an argument that is not an integer: `MC_NACK_CONFIG_KIND`; an axis beyond
 * `identity.num_axes`: `MC_NACK_BAD_AXIS`; a group beyond `MC_GROUP_COUNT`: `MC_NACK_BAD_GROUP`.
 */
#define MC_OP_READ_CONFIG 96

/**
 * Axis: the axis. args: counts per user unit (|scale| in `MC_SCALE_MIN..MC_SCALE_MAX`, negative:
 * the user's axis runs against the encoder; else `MC_NACK_OUT_OF_RANGE`, NaN:
 * `MC_NACK_NOT_FINITE`). Kept for hosts, read back in `axis_config.scale`; the card does not use
 * it. Any state.
 */
#define MC_OP_SET_SCALE 97

/**
 * Axis: the axis. args: points (`0..MC_COMP_MAX_POINTS`), bound (the largest |correction +
 * backlash/2| allowed, counts, > 0), backlash (counts, >= 0), ramp velocity (counts/s), ramp
 * acceleration (counts/s^2) (both in the kinematic limit range). flags: `MC_COMP_BIDIR`. A bad
 * count, bound, backlash, ramp or flags: `MC_NACK_COMP_TABLE`.
 */
#define MC_OP_COMP_TABLE 98

/**
 * Axis: the axis. args: index of the first point, count (`1..MC_COMP_DATA_MAX`), then position,
 * forward correction, reverse correction of each (counts). Every argument finite (else
 * `MC_NACK_NOT_FINITE`); no open table or out of order: `MC_NACK_COMP_SEQUENCE`; positions not
 * strictly increasing: `MC_NACK_COMP_ORDER`; a correction beyond the bound (with half the
 * backlash), or reverse != forward without `MC_COMP_BIDIR`: `MC_NACK_COMP_BOUND`.
 */
#define MC_OP_COMP_DATA 99

/**
 * Axis: the axis. args: index of the first point (`0..MC_COMP_MAX_POINTS`). Any state; taken
 * without a session (it reads).
 */
#define MC_OP_COMP_READ 100

/**
 * Axis: the axis. args: the period, counts (0: linear; else `MC_MODULO_MIN..MC_MODULO_MAX`,
 * rounded to 1/65536 count; NaN or infinite: `MC_NACK_NOT_FINITE`; out of range:
 * `MC_NACK_MODULO_RANGE`). Only at rest (Standstill with no motion, Disabled, or ErrorStop with no
 * motion; else `MC_NACK_MODULO_BUSY`). An armed compare channel watching the axis:
 * `MC_NACK_COMPARE_TURN` (layout 1.13). The positions are wrapped at once. Read back in
 * `axis_config.modulo`.
 */
#define MC_OP_SET_MODULO 101

/**
 * Axis: the axis (not in an enabled group). args: input (`0..MC_AUX_ENCODERS-1`, else
 * `MC_NACK_HANDWHEEL_INPUT`), ratio (axis counts per detent, a whole number, 1 <= |ratio| <=
 * `MC_HANDWHEEL_RATIO_MAX`; negative: the other way), detent (auxiliary counts per detent,
 * `1..MC_HANDWHEEL_DETENT_MAX`) (else `MC_NACK_HANDWHEEL_RATIO`). From Standstill, Discrete or
 * ContinuousMotion (Aborting: the target starts where the axis's jog ramp stops it) or the axis's
 * own handwheel (a new input or ratio, from the target it has: the motion and its seq go on). Ack
 * value: the seq of the handwheel's motion.
 */
#define MC_OP_HANDWHEEL 104

/**
 * Axis: the axis, whose handwheel runs (else `MC_NACK_INVALID_STATE`): the axis goes on to the
 * wheel's last target as a DiscreteMotion, `MC_EVENT_MOTION_DONE` with the seq of its
 * `MC_OP_HANDWHEEL`, then Standstill.
 */
#define MC_OP_HANDWHEEL_OFF 105

/**
 * `MC_GroupHome`. axis: the group. args: the stage count (0: the configured order), then each
 * stage's mask of group axes.
 */
#define MC_OP_GROUP_HOME 106

/**
 * Axis: the gantry (`0..MC_MAX_GANTRIES-1`). args: master, slaves n (`1..MC_GANTRY_MAX_SLAVES`),
 * kp (1/s^2), ki (1/s^3), skew limit (counts, > 0, in the position range), then each slave's axis
 * and square offset (counts, in the position range). Every member Standstill, or every member
 * Disabled. A gantry index, master or slave that is no axis of the card, a count out of range,
 * master == slave or a slave twice: `MC_NACK_GANTRY_AXES`; gains, limit or offset out of range:
 * `MC_NACK_GANTRY_GAINS`; a member in another gantry, a slave that is a member of a configured
 * group, a member geared, cammed or streaming: `MC_NACK_GANTRY_IN_USE`; the gantry formed already,
 * the members not all at rest with the same power: `MC_NACK_GANTRY_STATE`.
 */
#define MC_OP_GANTRY_FORM 108

/**
 * Axis: the gantry. The master at rest (Standstill, Disabled or ErrorStop with no ramp running),
 * else `MC_NACK_GANTRY_STATE` (as for a gantry not formed); the slaves hold where they are
 * (Standstill).
 */
#define MC_OP_GANTRY_DISSOLVE 109

/**
 * Axis: the gantry. Every member Standstill (else `MC_NACK_GANTRY_STATE`): each member runs its
 * own `MC_OP_HOME` (its `axis_homing` block, home position 0) with the coupling suspended; once
 * all are homed, each slave moves (within its homing block's velocity and acceleration) until
 * slave - master = its square offset, which becomes its hold; then the gantry is coupled again and
 * `MC_EVENT_GANTRY_HOMED` posts (code 0, value: slave 0's skew). A side that fails: the others
 * halt, the gantry is coupled where they stand, `MC_EVENT_GANTRY_HOMED` with the failure's
 * `MC_HOMING_ERROR_*` and the failing axis as value. The members' own `MC_EVENT_MOTION_DONE` /
 * `MC_EVENT_HOMING_FAILED` carry this seq.
 */
#define MC_OP_GANTRY_HOME 110

/**
 * Axis: the axis. args: slot (`0..MC_BIQUADS-1`), kind (`MC_BIQUAD_NOTCH.._RAW`), `freq_hz`,
 * damping, `depth_db`, `freq2_hz`, b0, b1, b2, a1, a2 (the arguments a kind does not use: 0). A
 * slot or kind out of range or not an integer: `MC_NACK_FILTER_KIND`; a number not finite:
 * `MC_NACK_NOT_FINITE`; a frequency <= 0 or >= `servo_rate_hz` / 2: `MC_NACK_FILTER_FREQ`; a
 * damping <= 0 or above 10, a depth out of -120..0, a raw |b| above `MC_BIQUAD_RAW_B_MAX`:
 * `MC_NACK_FILTER_PARAM`; the poles not inside the unit circle by `MC_BIQUAD_POLE_MARGIN`:
 * `MC_NACK_FILTER_UNSTABLE`.
 */
#define MC_OP_SERVO_FILTER_SET 112

/**
 * Axis: the axis. args: slot (`0..MC_BIQUADS-1`, else `MC_NACK_FILTER_KIND`); clearing an empty
 * slot is not an error.
 */
#define MC_OP_SERVO_FILTER_CLEAR 113

/**
 * Args: input (`0..MC_ANALOG_INPUTS-1`), `cutoff_hz` (0: no filter; else > 0 and at most half the
 * servo rate), threshold (V, within `+-MC_ANALOG_RANGE`), hysteresis (V, 0..2 `*`
 * `MC_ANALOG_RANGE`). flags: `MC_ANALOG_EV_RISE`, `MC_ANALOG_EV_FALL`. axis field ignored.
 */
#define MC_OP_ANALOG_INPUT 116

/**
 * Args: output (`0..MC_ANALOG_OUTPUTS-1`), volts (clamped to the DAC's range; NaN:
 * `MC_NACK_NOT_FINITE`). An output the PSO drives: `MC_NACK_ANALOG_CHANNEL`. axis field ignored.
 */
#define MC_OP_ANALOG_OUTPUT 117

/**
 * Axis: the group (configured, else `MC_NACK_PSO_GROUP`). args: output (a spare DAC
 * `0..MC_ANALOG_OUTPUTS-1`, or with `MC_PSO_PWM` a digital output `0..MC_CARD_OUTPUTS-1` no compare
 * channel pulses), gate (a digital output `0..MC_CARD_OUTPUTS-1`, not the PWM's), min, max (min <= max;
 * V within the DAC's range, or a duty 0..1), `v_ref` (counts/s, > 0), `pwm_hz` (`MC_PSO_PWM`:
 * `1..MC_PSO_PWM_HZ_MAX`; else ignored), `filter_hz` (0: none; else > 0 and at most half the servo
 * rate). flags: `MC_PSO_PWM`. Anything else out of range: `MC_NACK_PSO_CONFIG`. Replaces a PSO
 * running (its old output goes to 0 first).
 */
#define MC_OP_PSO 118

/**
 * The PSO stops; its output goes to 0 (0 V, or duty 0). Accepted when it is off. axis field
 * ignored.
 */
#define MC_OP_PSO_OFF 119

/**
 * Args: 1 pause at the end of a segment, 0 go on (above).
 */
#define MC_OP_PATH_PAUSE 120

/**
 * Axis: the axis. args: mode (`MC_FREQ_REF` or `MC_FREQ_OUTPUT`), `from_hz`, `to_hz`, points
 * (`1..MC_FREQ_POINTS_MAX`), amplitude (counts, or volts), cycles (periods measured per point,
 * `1..MC_FREQ_CYCLES_MAX`), `settle_s` (`0..MC_FREQ_SETTLE_MAX`: settle windows before each
 * measured one, at least one). A number not finite: `MC_NACK_NOT_FINITE`; a mode, count or
 * frequency out of range (`MC_FREQ_MIN_HZ` <= `from_hz` <= `to_hz` <= `servo_rate_hz` / 4):
 * `MC_NACK_FREQ_RANGE`; an amplitude <= 0, or above `dac_limit_v` (`MC_FREQ_OUTPUT`):
 * `MC_NACK_FREQ_AMPLITUDE`; `MC_FREQ_REF` with a sine beyond the axis's limits (amplitude 2 pi
 * `to_hz` above `axis_safety.max_velocity`, amplitude (2 pi `to_hz)^2` above the card's
 * acceleration range, 2 amplitude above `min_ferror`, the position held +- amplitude beyond the
 * soft limits in force): `MC_NACK_FREQ_LIMITS`; a sweep running (any axis): `MC_NACK_FREQ_BUSY`;
 * the axis disabled: `MC_NACK_AXIS_DISABLED`; not at rest in Standstill: `MC_NACK_INVALID_STATE`.
 */
#define MC_OP_FREQ_START 121

/**
 * Axis ignored: the sweep running ends (`MC_FREQ_ABORTED`, `MC_EVENT_FREQ_DONE`); none running:
 * accepted, nothing changes.
 */
#define MC_OP_FREQ_STOP 122

/**
 * Args: a, b, c (three distinct group axes, else `MC_NACK_ARC_AXES`; beyond the group:
 * `MC_NACK_AXIS_NOT_IN_GROUP`), `n_a`, `n_b`, `n_c` (the normal, any length but not 0:
 * `MC_NACK_ARC_NORMAL`; NaN: `MC_NACK_NOT_FINITE`). The group's normal plane for the following
 * `MC_OP_PATH_ARC_NORMAL` (configured group).
 */
#define MC_OP_PATH_ARC_PLANE 124

/**
 * Args: id, feed, tolerance (as `MC_OP_PATH_LINE`), `centre_a`, `centre_b`, `centre_c`, `end_a`,
 * `end_b`, `end_c`, then the targets of the other group axes in order (a helix). flags:
 * `MC_MOVE_RELATIVE` (the centre, end and targets from the path's end), `MC_CIRC_HELIX_RELATIVE`
 * (the other axes' targets are distances), `MC_ARC_RISE`, `MC_PATH_*`. No plane set:
 * `MC_NACK_ARC_NORMAL`.
 */
#define MC_OP_PATH_ARC_NORMAL 125

/**
 * Args: tick (the card tick to run the next entry on: > the card's tick, within
 * `MC_TIMED_MAX_AHEAD` ticks), key (0: none, else 1..2^32-1: run only once `MC_OP_SYNC_COMMIT` of
 * it is seen).
 */
#define MC_OP_AT_TICK 126

/**
 * Args: key (1..2^32-1), tick (the commands' tick). On the bus's master or a card alone:
 * `MC_NACK_COMMIT_LATE` unless tick > the card's tick; a follower: `MC_NACK_NOT_MASTER`.
 */
#define MC_OP_SYNC_COMMIT 127

/**
 * Args: key (0: every held command). Ack value: the commands dropped.
 */
#define MC_OP_TIMED_CANCEL 128

/**
 * Args: v, a, d, j, `centre_a`, `centre_b`, `centre_c`, `end_a`, `end_b`, `end_c` (on the plane's
 * axes), turns (whole, >= 0: `MC_NACK_OUT_OF_RANGE`). flags: `MC_MOVE_RELATIVE`,
 * `MC_MOVE_BUFFERED`, the feed type, `MC_ARC_RISE`, `MC_CIRC_HELIX_RELATIVE`.
 */
#define MC_OP_GROUP_MOVE_CIRCULAR_NORMAL 129

/**
 * The second entry of `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL`: args: a, b, c (three distinct group
 * axes, else `MC_NACK_ARC_AXES`; beyond the group: `MC_NACK_AXIS_NOT_IN_GROUP`), `n_a`, `n_b`,
 * `n_c` (the normal, not 0: `MC_NACK_ARC_NORMAL`), then the targets of the other group axes in
 * group order (a helix).
 */
#define MC_OP_GROUP_CIRCULAR_PLANE 131

/**
 * Copy and validate `group_dims[group]` (above).
 */
#define MC_OP_APPLY_GROUP_DIMS 132

/**
 * Args: the targets of the segment's dimensions past those its own entry holds, in order (a line:
 * dimensions 8..; an arc: the helix's dimensions after its first 6). Only right after the
 * segment's entry of the same group (above).
 */
#define MC_OP_PATH_MORE 133

/**
 * Args: count (a whole number `1..path_staged`, else `MC_NACK_PATH_RELEASE`; more than the path
 * has room for: `MC_NACK_QUEUE_FULL`). Nothing released on a refusal.
 */
#define MC_OP_PATH_RELEASE 134

/**
 * `mc_pso_info.state`: not configured.
 */
#define MC_PSO_STATE_OFF 0

/**
 * `mc_pso_info.state`: configured, its gate output off: the output is 0.
 */
#define MC_PSO_STATE_CLOSED 1

/**
 * `mc_pso_info.state`: the gate output on: the output follows the path speed.
 */
#define MC_PSO_STATE_ON 2

/**
 * `mc_freq_sweep.mode`: the sine on the position reference (user units): the closed loop.
 */
#define MC_FREQ_MODE_REFERENCE 0

/**
 * `mc_freq_sweep.mode`: the sine on the servo output (volts): the plant and the open loop.
 */
#define MC_FREQ_MODE_OUTPUT 1

/**
 * Most slaves of a gantry.
 */
#define MC_GANTRY_SLAVES_MAX 4

/**
 * `mc_gcode_poll` / `mc_gcode_run`: items are queued or run.
 */
#define MC_GCODE_RUNNING 0

/**
 * Waiting for the motion queued so far to end (before a spindle, tool or pause operation,
 * or at the end).
 */
#define MC_GCODE_DRAINING 1

/**
 * Paused (M0, M1 with the optional stop on, M60, or `mc_gcode_pause`), the motion ended:
 * `mc_gcode_resume` goes on.
 */
#define MC_GCODE_PAUSED 2

/**
 * The program ended and all its motion is done.
 */
#define MC_GCODE_DONE 3

/**
 * Aborted (`mc_gcode_abort`, or an error: `mc_gcode_error` says which line): nothing more
 * is read.
 */
#define MC_GCODE_ABORTED 4

/**
 * The default detent of `mc_handwheel_select`: 4 auxiliary counts (a quadrature wheel with
 * one detent per cycle, 100 detents a turn).
 */
#define MC_HANDWHEEL_DEFAULT_DETENT 4

/**
 * Homing method: a hard stop (a mechanical end stop) in the negative direction, found as a
 * following error of `hard_stop_ferror` held `hard_stop_dwell`, then the index pulse away from
 * it.
 */
#define MC_HOMING_METHOD_HARD_STOP_NEG_INDEX -1

/**
 * Homing method: a hard stop in the positive direction, then the index pulse.
 */
#define MC_HOMING_METHOD_HARD_STOP_POS_INDEX -2

/**
 * Homing method: a hard stop in the negative direction: the home point is where the axis
 * stalled.
 */
#define MC_HOMING_METHOD_HARD_STOP_NEG -3

/**
 * Homing method: a hard stop in the positive direction.
 */
#define MC_HOMING_METHOD_HARD_STOP_POS -4

/**
 * Homing method: the current position (nothing moves).
 */
#define MC_HOMING_METHOD_CURRENT_POSITION 37

/**
 * Compare direction: fire crossing upwards (increasing position).
 */
#define MC_COMPARE_POSITIVE 1

/**
 * Compare direction: fire crossing downwards.
 */
#define MC_COMPARE_NEGATIVE 2

/**
 * Compare direction: either way (`mc_compare_single` only).
 */
#define MC_COMPARE_EITHER 3

/**
 * `mc_move` kind: MC_MoveAbsolute, `value` is the target.
 */
#define MC_MOVE_KIND_ABSOLUTE 0

/**
 * `mc_move` kind: MC_MoveRelative, `value` is a distance from the commanded position
 * (buffered: from the target of the move before it).
 */
#define MC_MOVE_KIND_RELATIVE 1

/**
 * `mc_move` kind: MC_MoveAdditive, `value` is a distance from the target of the last move.
 */
#define MC_MOVE_KIND_ADDITIVE 2

/**
 * PLCopen BufferMode Aborting: take over at once from the current position, velocity and
 * acceleration; the motion in progress and every buffered move are aborted.
 */
#define MC_BUFFER_ABORTING 0

/**
 * PLCopen BufferMode Buffered: wait in the axis's queue (16 moves, else `MC_ERR_QUEUE_FULL`)
 * until the motion before it is done; `mc_motion_wait_active` tells when it starts.
 */
#define MC_BUFFER_BUFFERED 1

/**
 * `mc_path_segment.kind`: a straight line to `target` (`naxes` values, one per group axis).
 */
#define MC_SEGMENT_LINE 0

/**
 * An arc in `plane` described by `arc` (a helix when `naxes` targets of the group's other
 * axes are given in `target`).
 */
#define MC_SEGMENT_ARC 1

/**
 * An exact stop, then a wait of `seconds` (0 < seconds <= the card's longest move time).
 */
#define MC_SEGMENT_DWELL 2

/**
 * Not a segment: an output action (`output`, `on`, `at`, `distance`) for the next motion
 * segment queued after it. It takes no room in the buffer; at most 8 may wait for their
 * segment (`MC_ERR_PATH_OUTPUT`).
 */
#define MC_SEGMENT_OUTPUT 3

/**
 * A NURBS curve (`curve`, as the arguments of `mc_group_move_nurbs`: control points in group
 * axis order and user units), run within `fit_tolerance` (> 0, user units of the first axis)
 * of the curve. It must start within `fit_tolerance` of where the segment before ends
 * (`MC_ERR_NURBS_START`; `relative`: its control points are from there). On the card it takes
 * one buffer entry per piece (quintics fitted to the curve, curvature-continuous where it
 * is): `mc_group_path_stream` waits until they fit, `mc_group_path_push` answers
 * `MC_ERR_QUEUE_FULL`; `MC_ERR_PATH_CURVE` for a cusp or more pieces than the buffer holds.
 * The curve's arrays are read during the call that queues it.
 */
#define MC_SEGMENT_NURBS 4

/**
 * Layout 1.12: an arc in the plane of three group axes given by a normal vector
 * (`plane_axes`, `normal`): counter-clockwise about the normal (the right-hand rule), in the
 * plane through the start, around `centre` to `end` (both on the three axes, in order; an end
 * at the start: a full turn); `rise` non-zero lets the end lie off the plane along the normal
 * (a helix along it). The targets of the group's other axes in group order (a helix) in
 * `target`, or none (`naxes` 0). The three axes need one scale. The card refuses a zero
 * normal (`MC_ERR_ARC_NORMAL`), an axis twice (`MC_ERR_ARC_AXES`), a centre or end off the
 * plane (`MC_ERR_ARC_OFF_PLANE`) or an end off the circle (`MC_ERR_CENTRE_NOT_EQUIDISTANT`) by
 * more than the group's tolerance.
 */
#define MC_SEGMENT_ARC_NORMAL 5

/**
 * No pause asked for (`mc_group_path_pause_state`).
 */
#define MC_PATH_PAUSE_NONE 0

/**
 * Braking for the pause point.
 */
#define MC_PATH_PAUSE_PAUSING 1

/**
 * At rest on it.
 */
#define MC_PATH_PAUSE_PAUSED 2

/**
 * `mode` of `mc_pvt_begin`: PT, the card estimates each point's velocity from its neighbours
 * (the stream starts, and at a last point ends, at rest).
 */
#define MC_PVT_MODE_PT 0

/**
 * PVT: each point's velocity as given.
 */
#define MC_PVT_MODE_PVT 1

/**
 * Cards a set may hold.
 */
#define MC_SYNC_CARDS_MAX 16

/**
 * `mc_event.axis` of an event about the whole card.
 */
#define MC_EVENT_CARD_WIDE 65535

/**
 * Acc/dec mode (`mc_group_settings.accdec`), besides `MC_GROUP_ACCDEC_PRE` and
 * `MC_GROUP_ACCDEC_POST`: both, the S-curve, then the filters.
 */
#define MC_GROUP_ACCDEC_BOTH (MC_GROUP_ACCDEC_PRE | MC_GROUP_ACCDEC_POST)

/**
 * Feed type (`mc_move_options.feed_type`), which selects each axis's acc/dec filter: cutting
 * feed (G01/G02/G03). 0, so a zeroed `mc_move_options` is the default.
 */
#define MC_FEED_TYPE_CUTTING 0

/**
 * Rapid traverse (G00).
 */
#define MC_FEED_TYPE_RAPID 1

/**
 * Jog.
 */
#define MC_FEED_TYPE_JOG 2

/**
 * `MC_ARC_PLANE_AXES`: a plane value names its two group axes u and v (counter-clockwise
 * from u towards v) as `MC_ARC_PLANE_AXES | u << MC_ARC_PLANE_U_SHIFT | v <<
 * MC_ARC_PLANE_V_SHIFT` (u, v 0..7; one axis twice is `MC_ERR_PLANE_AXES`).
 */
#define MC_ARC_PLANE_U_SHIFT 8

/**
 * See `MC_ARC_PLANE_U_SHIFT`.
 */
#define MC_ARC_PLANE_V_SHIFT 12

/**
 * Clock of an emulated card (`mc_sim_options.clock`): paced to the servo rate in real time,
 * as `mc_open("sim")`.
 */
#define MC_SIM_CLOCK_REAL_TIME 0

/**
 * As fast as the host can compute the ticks. The card's watchdog counts card time, which then
 * runs far ahead of the library's heartbeat: raise the timeout (`mc_set_watchdog_timeout`) and
 * clear a trip (`mc_reset_faults`) before enabling axes.
 */
#define MC_SIM_CLOCK_FREE_RUNNING 1

/**
 * Time advances only in `mc_sim_step` and in waits (as `mc_open_sim_stepped`).
 */
#define MC_SIM_CLOCK_STEPPED 2

/**
 * Plant of an emulated card (`mc_sim_options.plant`): the default servo motor on every axis.
 */
#define MC_SIM_PLANT_DEFAULT 0

/**
 * Yeh's die bonder (Table 1): its X plant on axis 0, its Y plant on the other axes. Pair it
 * with `mc_pdplus_settings_die_bonder` and a 1000 Hz servo rate, as in the paper.
 */
#define MC_SIM_PLANT_DIE_BONDER 1

/**
 * What every `mc_` function returns: `MC_OK` (0) on success, a negative `MC_ERR_` code on
 * failure. The codes are stable: a code keeps its number in every later version.
 */
typedef int32_t mc_result;

/**
 * A card handle: an integer, as in vendor libraries' card numbers. 0 is never a valid handle.
 */
typedef uint32_t mc_card;

/**
 * An analog input's filter and threshold (`mc_analog_input_configure`). All zero: the boot
 * state (no filter, threshold 0 V, no hysteresis, no events).
 */
typedef struct mc_analog_input_settings {
  /**
   * The first-order filter's cut-off, Hz (0: none; at most half the servo rate).
   */
  double cutoff_hz;
  /**
   * The threshold, V (within +-10 V).
   */
  double threshold;
  /**
   * The hysteresis, V (0..20): the input is below again at `threshold - hysteresis`.
   */
  double hysteresis;
  /**
   * Nonzero: an `MC_EVENT_ANALOG` event (axis: the input, code 1) going above.
   */
  uint32_t rise_event;
  /**
   * Nonzero: an `MC_EVENT_ANALOG` event (code 0) going below again.
   */
  uint32_t fall_event;
} mc_analog_input_settings;

/**
 * An analog input as the card sampled it at its last tick (`mc_analog_input_read`).
 */
typedef struct mc_analog_input_info {
  /**
   * The 16-bit ADC's sample, V (a multiple of 20/65536 V).
   */
  double sample;
  /**
   * The filtered value, V.
   */
  double value;
  /**
   * 1 while above the threshold.
   */
  uint32_t above;
  /**
   * Reserved (0).
   */
  uint32_t reserved;
  /**
   * The settings the card holds.
   */
  struct mc_analog_input_settings settings;
} mc_analog_input_info;

/**
 * The path-speed output's settings (`mc_pso_configure`).
 */
typedef struct mc_pso_settings {
  /**
   * 0: a spare DAC output (`output` 0..3, `min`/`max` in volts); nonzero: a PWM on digital
   * output `output` (0..15) at `pwm_hz`, `min`/`max` duties 0..1.
   */
  uint32_t pwm;
  /**
   * The output.
   */
  uint32_t output;
  /**
   * The digital output (0..15) whose level switches the PSO on (the path's M62..M65).
   */
  uint32_t gate;
  /**
   * Reserved (0).
   */
  uint32_t reserved;
  /**
   * The output at rest.
   */
  double min;
  /**
   * The output at `v_ref` and beyond.
   */
  double max;
  /**
   * The tangential speed of full output, the group's user units per second (> 0).
   */
  double v_ref;
  /**
   * The PWM's frequency, Hz (1..100000; ignored for a DAC).
   */
  double pwm_hz;
  /**
   * The speed filter's cut-off, Hz (0: none; at most half the servo rate).
   */
  double filter_hz;
} mc_pso_settings;

/**
 * The path-speed output's state of the last tick (`mc_pso_get_info`).
 */
typedef struct mc_pso_info {
  /**
   * `MC_PSO_STATE_*`.
   */
  uint32_t state;
  /**
   * Its group.
   */
  uint32_t group;
  /**
   * The group's actual tangential speed, encoder counts per second.
   */
  double speed_counts;
  /**
   * The output: V, or the PWM's duty.
   */
  double value;
} mc_pso_info;

/**
 * How `mc_open_sim` builds an emulated card. Start from `mc_sim_options_default`.
 */
typedef struct mc_sim_options {
  /**
   * `MC_SIM_CLOCK_` value.
   */
  uint32_t clock;
  /**
   * Axes, 1..8.
   */
  uint32_t axes;
  /**
   * Servo rate, 1000..20000 Hz.
   */
  uint32_t servo_rate_hz;
  /**
   * `MC_SIM_PLANT_` value.
   */
  uint32_t plant;
} mc_sim_options;

/**
 * What the card says about itself (`mc_card_info`).
 */
typedef struct mc_card_info {
  /**
   * Firmware version, `major << 16 | minor << 8 | patch`.
   */
  uint32_t firmware_version;
  /**
   * DPRAM layout major version.
   */
  uint16_t layout_major;
  /**
   * DPRAM layout minor version.
   */
  uint16_t layout_minor;
  /**
   * Axes on the card (axis numbers 0 .. axes-1).
   */
  uint32_t axes;
  /**
   * Servo rate, Hz.
   */
  uint32_t servo_rate_hz;
  /**
   * `MC_CARD_CAP_` bits.
   */
  uint32_t capabilities;
} mc_card_info;

/**
 * FFPIV gains (Thinh Fig 5) and the velocity estimator's cut-off: part of mc_axis_config.
 */
typedef struct mc_ffpiv_gains {
  /**
   * Position gain K_P, 1/s: velocity command = kp * following error.
   */
  double kp;
  /**
   * Velocity-loop integral gain K_I, 1/s.
   */
  double ki;
  /**
   * Velocity-loop gain K_V, V per count/s.
   */
  double kv;
  /**
   * Velocity feed-forward K_VFF into the velocity loop, fraction 0..2.
   */
  double kvff;
  /**
   * Acceleration feed-forward K_AFF, V per count/s^2.
   */
  double kaff;
  /**
   * Cut-off of the first-order filter on the measured velocity, Hz.
   */
  double vel_filter_hz;
} mc_ffpiv_gains;

/**
 * An axis's servo configuration. Host writes; the card validates and copies it on
 * MC_OP_APPLY_AXIS_CONFIG.
 */
typedef struct mc_axis_config {
  /**
   * MC_SERVO_*: FFPIV, or PD+ with the gains of `axis_pdplus[axis]`.
   */
  uint32_t servo_law;
  uint32_t _reserved0;
  /**
   * The FFPIV gains.
   */
  struct mc_ffpiv_gains ffpiv;
  /**
   * Output clamp, V, 0 < limit <= 10.
   */
  double dac_limit_v;
  /**
   * |target - actual| for motion done, counts.
   */
  double in_pos_window;
  /**
   * |actual velocity| for motion done, counts/s.
   */
  double in_vel_window;
  /**
   * Both windows held this long before motion done, s.
   */
  double settle_time;
  /**
   * Layout 1.5: the largest jog velocity, counts/s (> 0).
   */
  double jog_max_vel;
  /**
   * Jog acceleration and deceleration, counts/s^2 (> 0).
   */
  double jog_accel;
  /**
   * Jog jerk, counts/s^3 (> 0).
   */
  double jog_jerk;
  /**
   * Layout 1.8: counts per user unit, kept for hosts (the card does not use it). The card
   * writes it on MC_OP_READ_CONFIG; MC_OP_SET_SCALE sets it; MC_OP_APPLY_AXIS_CONFIG ignores
   * it. 1 at boot.
   */
  double scale;
  /**
   * Layout 1.10: the modulo period, counts (0: a linear axis). The card writes it on
   * MC_OP_READ_CONFIG; MC_OP_SET_MODULO sets it; MC_OP_APPLY_AXIS_CONFIG ignores it. 0 at
   * boot.
   */
  double modulo;
} mc_axis_config;

/**
 * Servo gains and in-position windows of an axis (counts, seconds, volts): the card's
 * `mc_axis_config` register block, the same struct as in the register map. Start from
 * `mc_axis_settings_default`; `mc_configure` selects FFPIV whatever `servo_law` holds.
 */
typedef struct mc_axis_config mc_axis_settings;

/**
 * Limits of a point-to-point move, in user units (see `mc_set_scale`). Every value must be
 * finite and greater than zero.
 */
typedef struct mc_move_limits {
  /**
   * Maximum velocity.
   */
  double velocity;
  /**
   * Maximum acceleration.
   */
  double acceleration;
  /**
   * Maximum deceleration.
   */
  double deceleration;
  /**
   * Jerk of the seven-segment phases 1, 3 (acceleration) and 5, 7 (deceleration).
   */
  double jerk[4];
} mc_move_limits;

/**
 * A motion started by `mc_move_absolute`, `mc_move_relative`, `mc_halt` or `mc_stop`; wait for
 * it with `mc_motion_wait`.
 */
typedef struct mc_motion {
  /**
   * The axis.
   */
  uint32_t axis;
  /**
   * The seq of the command that started it (events about it carry the same seq).
   */
  uint32_t seq;
} mc_motion;

/**
 * What the card publishes about an axis each tick (counts, seconds, volts): the payload of
 * the axis status seqlock, copied as MC_STATUS_WORDS 64-bit words.
 */
typedef struct mc_axis_status_payload {
  /**
   * Commanded (profile) position, counts.
   */
  double cmd_pos;
  /**
   * Commanded velocity, counts/s.
   */
  double cmd_vel;
  /**
   * Commanded acceleration, counts/s^2.
   */
  double cmd_acc;
  /**
   * Actual position, counts: the encoder's, less the compensation's correction (layout 1.9:
   * where the load is; the encoder's own without compensation).
   */
  double act_pos;
  /**
   * Actual velocity (filtered), counts/s.
   */
  double act_vel;
  /**
   * Following error = commanded - actual position, counts.
   */
  double ferr;
  /**
   * DAC output, volts.
   */
  double dac_v;
  /**
   * Target of the current or last move, counts.
   */
  double target;
  /**
   * PLCopen state, MC_AXIS_STATE_*.
   */
  uint32_t state;
  /**
   * Fault bits, MC_AXIS_FAULT_*.
   */
  uint32_t faults;
  /**
   * Seq of the last command accepted for this axis.
   */
  uint32_t last_seq;
  /**
   * Moves started since boot: each of the axis's own moves, and each group motion it takes
   * part in counts one (a continuous path, from the group leaving Standby until it is at
   * rest again, is one move however many segments it runs).
   */
  uint32_t move_count;
  /**
   * Servo tick of this snapshot.
   */
  uint64_t tick;
  /**
   * Raw encoder count.
   */
  int64_t encoder;
  /**
   * Max |commanded velocity| of the current or last move (statistics of the current or
   * last move are reset when a move starts; a group motion, a whole continuous path
   * included, is one move: its peaks, following error and time), counts/s.
   */
  double peak_vel;
  /**
   * Max commanded acceleration in the direction of motion, counts/s^2.
   */
  double peak_acc;
  /**
   * Max commanded deceleration, counts/s^2.
   */
  double peak_dec;
  /**
   * Max |commanded jerk|, counts/s^3.
   */
  double peak_jerk;
  /**
   * Max |following error|, counts.
   */
  double max_ferr;
  /**
   * Planned profile duration, s.
   */
  double planned_time;
  /**
   * From start to motion done (in position), s; 0 while moving.
   */
  double move_time;
  /**
   * Payload word 19: why the last motion ended, MC_STOP_*.
   */
  uint32_t stop_reason;
  /**
   * Input and drive-enable bits, MC_IO_*.
   */
  uint32_t io;
  /**
   * Payload word 20: the servo law's output before the DAC clamp, V.
   */
  double u_request;
  /**
   * Payload word 21 (layout 1.5): MC_MOTION_* bits.
   */
  uint32_t motion_flags;
  /**
   * Buffered moves waiting in the axis's queue.
   */
  uint32_t queued;
  /**
   * Payload word 22: the velocity override factor in force, 0..MC_OVERRIDE_MAX.
   */
  double override_factor;
  /**
   * Payload word 23 (layout 1.9): the compensated position, the motor's reference the servo
   * follows: cmd_pos + the pitch-error and backlash correction, counts (cmd_pos without
   * compensation).
   */
  double comp_pos;
  /**
   * A mix of the words before it: the checksum the seqlock reader checks.
   */
  uint64_t checksum;
} mc_axis_status_payload;

/**
 * Everything the card publishes about an axis, in counts and seconds (no scale applied): the
 * card's `mc_axis_status_payload`, the same struct as in the register map (`state` is an
 * `MC_AXIS_STATE_` value, `faults` `MC_AXIS_FAULT_` bits, `stop_reason` an
 * `MC_STOP_REASON_` value, `io` `MC_IO_` bits; `checksum` is 0: the library checked it).
 */
typedef struct mc_axis_status_payload mc_raw_status;

/**
 * A consistent snapshot of an axis's status, in user units (see `mc_set_scale`), with
 * everything the card published in counts in `raw`.
 */
typedef struct mc_status {
  /**
   * `MC_AXIS_STATE_` value.
   */
  uint32_t state;
  /**
   * `MC_AXIS_FAULT_` bits.
   */
  uint32_t faults;
  /**
   * Commanded position.
   */
  double command_position;
  /**
   * Commanded velocity.
   */
  double command_velocity;
  /**
   * Commanded acceleration.
   */
  double command_acceleration;
  /**
   * Actual position.
   */
  double actual_position;
  /**
   * Actual velocity.
   */
  double actual_velocity;
  /**
   * Following error (commanded − actual).
   */
  double following_error;
  /**
   * DAC output, volts.
   */
  double dac_volts;
  /**
   * The same snapshot in counts, with the card's per-move statistics.
   */
  mc_raw_status raw;
  /**
   * Why the last motion ended (`MC_STOP_REASON_` value; a newer card may report one this
   * library has no constant for).
   */
  uint32_t stop_reason;
  /**
   * The axis's limit switch, home, amplifier alarm, encoder fault and e-stop inputs and its
   * drive-enable output (`MC_IO_` bits).
   */
  uint32_t io;
} mc_status;

/**
 * An event from the card. The unit rule, one for every kind: a `value` that is a position
 * or a distance is in user units of the axis it concerns (`axis`, or for `MC_EVENT_COMPARE`
 * and `MC_EVENT_PROBE` the axis the channel watches), as `mc_status` gives them: motion done
 * and active, in velocity (user units/s), homing failed, sync, PVT done, compare fired or
 * missed, probe captures, and the safety stops whose measurement is a position, a following
 * error or an encoder count. Every other value is as the card posts it: states, times in
 * seconds, counts of things, ids, words.
 */
typedef struct mc_event {
  /**
   * `MC_EVENT_` value.
   */
  uint32_t kind;
  /**
   * Axis, or `MC_EVENT_CARD_WIDE`.
   */
  uint32_t axis;
  /**
   * Seq of the command it concerns (motion events: the command that started the motion;
   * compare with `mc_motion.seq`).
   */
  uint32_t seq;
  /**
   * Kind-specific code.
   */
  int32_t code;
  /**
   * Servo tick at which the card raised it.
   */
  uint64_t tick;
  /**
   * Kind-specific value (positions and distances in user units: the rule above).
   */
  double value;
} mc_event;

/**
 * The event callback: called from `mc_dispatch_events`, on the thread that called it, once
 * per event. `event` is valid only during the call. `user` is the pointer given to
 * `mc_set_event_callback`.
 */
typedef void (*mc_event_callback)(mc_card card, const struct mc_event *event, void *user);

/**
 * Which cam table, and how it maps the master onto the slave (counts): slave = slave_offset +
 * slave_scale × table((master − master_offset) / master_scale).
 */
typedef struct mc_cam_settings {
  /**
   * Table 0 .. `MC_CAM_TABLES` − 1.
   */
  uint32_t table;
  /**
   * Subtracted from the master's position, counts.
   */
  double master_offset;
  /**
   * Added to the table's slave position, counts.
   */
  double slave_offset;
  /**
   * Divides the master's position (nonzero).
   */
  double master_scale;
  /**
   * Multiplies the table's slave position (nonzero).
   */
  double slave_scale;
  /**
   * Nonzero: PLCopen StartMode relative (the card shifts the slave offset so the cam starts
   * where the slave stands). 0: absolute, ramped in within the limits.
   */
  uint32_t relative;
} mc_cam_settings;

/**
 * The slave's own limits while it engages, in its user units.
 */
typedef struct mc_sync_limits {
  /**
   * Velocity.
   */
  double velocity;
  /**
   * Acceleration (and deceleration).
   */
  double acceleration;
  /**
   * Jerk.
   */
  double jerk;
} mc_sync_limits;

/**
 * An axis's compensation settings, in the axis's user units and seconds.
 */
typedef struct mc_comp_settings {
  /**
   * Nonzero: each point gives a forward and a reverse correction (else they must be equal).
   */
  uint32_t bidirectional;
  /**
   * Backlash (>= 0): +backlash/2 moving forward, -backlash/2 in reverse.
   */
  double backlash;
  /**
   * The largest |correction ± backlash/2| allowed (> 0).
   */
  double bound;
  /**
   * The velocity of the ramp that takes up a jump of the correction (> 0).
   */
  double ramp_velocity;
  /**
   * Its acceleration (> 0).
   */
  double ramp_acceleration;
} mc_comp_settings;

/**
 * One point of a compensation table, user units.
 */
typedef struct mc_comp_table_point {
  /**
   * Position (strictly increasing along the table).
   */
  double position;
  /**
   * Correction moving forward.
   */
  double forward;
  /**
   * Correction moving in reverse.
   */
  double reverse;
} mc_comp_table_point;

/**
 * A sweep: `points` frequencies log-spaced from `from_hz` to `to_hz` (0.1 Hz <= from <= to
 * <= a quarter of the servo rate, 1..256 points), the sine's `amplitude` (user units, or
 * volts with `MC_FREQ_MODE_OUTPUT`), `cycles` periods measured at each (1..1000; the card
 * measures at least 1000 servo ticks) after at least `settle_s` seconds of settling (0..60).
 */
typedef struct mc_freq_sweep {
  /**
   * `MC_FREQ_MODE_REFERENCE` or `MC_FREQ_MODE_OUTPUT`.
   */
  uint32_t mode;
  uint32_t points;
  double from_hz;
  double to_hz;
  double amplitude;
  uint32_t cycles;
  uint32_t _reserved0;
  double settle_s;
} mc_freq_sweep;

/**
 * One point of a measured response: the mode's response (the closed loop X/D, or the plant
 * X/U with `MC_FREQ_MODE_OUTPUT`), the plant (user units per volt) and the open loop, gain in
 * dB and phase in degrees.
 */
typedef struct mc_freq_point {
  /**
   * The frequency the card ran, Hz.
   */
  double hz;
  double gain_db;
  double phase_deg;
  double plant_gain_db;
  double plant_phase_deg;
  double open_gain_db;
  double open_phase_deg;
} mc_freq_point;

/**
 * A resonance (or anti-resonance: `anti` 1) found in the mode's response.
 */
typedef struct mc_freq_resonance {
  double hz;
  /**
   * The response's gain there, dB.
   */
  double gain_db;
  /**
   * How far it stands out of its neighbours, dB.
   */
  double height_db;
  uint32_t anti;
  uint32_t _reserved0;
} mc_freq_resonance;

/**
 * A gantry's yaw loop and skew limit (the limit in the master's user units).
 */
typedef struct mc_gantry_settings {
  /**
   * Proportional gain of the yaw loop, 1/s² (0..1e9): the slave's acceleration correction
   * per count of skew.
   */
  double kp;
  /**
   * Integral gain of the yaw loop, 1/s³ (0..1e12).
   */
  double ki;
  /**
   * The skew beyond which every axis of the gantry stops (> 0).
   */
  double skew_limit;
} mc_gantry_settings;

/**
 * A gantry as the card reports it (the master's user units).
 */
typedef struct mc_gantry_info {
  /**
   * 1 coupled, 2 homing, 3 squaring (`MC_GANTRY_*` of the register map).
   */
  uint32_t phase;
  /**
   * The master axis.
   */
  uint32_t master;
  /**
   * Slaves in use.
   */
  uint32_t nslaves;
  /**
   * Nonzero once `mc_gantry_home` squared the bridge.
   */
  uint32_t squared;
  /**
   * The slave axes.
   */
  uint32_t slave[4];
  /**
   * Each slave's skew of the last tick: slave actual - master actual - offset in force.
   */
  double skew[4];
  /**
   * Each slave's largest |skew| while coupled since the gantry was formed.
   */
  double max_skew[4];
  /**
   * Each slave's offset in force.
   */
  double hold[4];
} mc_gantry_info;

/**
 * How a program runs (`mc_gcode_default_settings` fills the defaults).
 */
typedef struct mc_gcode_settings {
  /**
   * The program's axis letter of each group axis in group order, NUL-terminated: "XYZ"
   * (the default), "XYZA", ... Arcs need X, Y, Z as the group's first three axes. The
   * group's axes are taken to be in mm and degrees.
   */
  char axes[8];
  /**
   * Rapid (G0) speed, mm/s.
   */
  double rapid_feed;
  /**
   * The largest feed, mm/s: a faster programmed feed runs at this.
   */
  double max_feed;
  /**
   * Corner tolerance of G64 without P, mm (a P in the program wins).
   */
  double tolerance;
  /**
   * How closely splines (G5) are followed, mm.
   */
  double spline_tolerance;
  /**
   * 1: lines starting with '/' are skipped.
   */
  uint32_t block_delete;
  /**
   * 1: M1 pauses.
   */
  uint32_t optional_stop;
  /**
   * The card's digital input (0..15) the touch probe of G38.2–G38.5 is wired to; -1
   * (the default): none, a probing move is then an error.
   */
  int32_t probe_input;
  /**
   * The spindle's card axis (enabled, not one of the group's; its user unit a revolution:
   * its scale the encoder's counts per revolution, whole revolutions its index), or -1
   * (the default): no spindle on the card, the spindle hook only, G33/G33.1 refused. With
   * one, M3/M4 with S turn it (M3 forward), M5 halts it, and G33/G33.1 follow its encoder.
   */
  int32_t spindle_axis;
  /**
   * The card output M7 sets (M9 clears), or -1 (the default): none.
   */
  int32_t mist_output;
  /**
   * The card output M8 sets (M9 clears), or -1 (the default): none.
   */
  int32_t flood_output;
  /**
   * The spindle's largest speed, rpm (default 3000): a larger S runs at this, with a
   * message.
   */
  double spindle_max_rpm;
  /**
   * The spindle's acceleration, rev/s² (default 100).
   */
  double spindle_acceleration;
  /**
   * The spindle's jerk, rev/s³ (default 2000).
   */
  double spindle_jerk;
  /**
   * 1 (the default): the run is measured as it goes, for `mc_gcode_report`; 0: not.
   */
  uint32_t report;
} mc_gcode_settings;

/**
 * A program handle: an integer (`generation << 16 | (slot + 1)`, as card handles). 0 is
 * never a handle.
 */
typedef uint32_t mc_gcode;

/**
 * The host's hooks, called inside `mc_gcode_poll` and `mc_gcode_run` once the motion
 * before the operation has ended (the message hook does not wait). Each may be NULL: the
 * operation is then passed, except M100–M199, which are then an error
 * (`MC_ERR_UNSUPPORTED`). A hook returning non-zero stops the run with that code.
 * `direction`: 3 (M3, clockwise), 4 (M4) or 5 (M5, off). `pause`: 0 M0, 1 M1, 2 M60;
 * return 1 to pause, 0 to go on. `user` is the pointer given to `mc_gcode_set_hooks`.
 */
typedef struct mc_gcode_hooks {
  /**
   * M3/M4/M5 and S (rpm).
   */
  int32_t (*spindle)(double speed, uint32_t direction, void *user);
  /**
   * M7/M8/M9: mist and flood on (1) or off (0).
   */
  int32_t (*coolant)(uint32_t mist, uint32_t flood, void *user);
  /**
   * M6 with its T.
   */
  int32_t (*tool_change)(uint32_t tool, void *user);
  /**
   * (MSG, ...): `text` is valid during the call.
   */
  void (*message)(uint32_t line, const char *text, void *user);
  /**
   * M100-M199 with P and Q (`has_p`, `has_q`: 1 when given).
   */
  int32_t (*hook)(uint32_t code, uint32_t has_p, double p, uint32_t has_q, double q, void *user);
  /**
   * M0, M1, M60.
   */
  int32_t (*pause)(uint32_t kind, void *user);
} mc_gcode_hooks;

/**
 * What a run did (`mc_gcode_report`), measured from the X, Y and Z axes' commanded and
 * actual positions of every tick the run saw: each poll of `mc_gcode_poll` or
 * `mc_gcode_run` samples the card once, so on a stepped card (`mc_gcode_run` steps it a
 * tick a poll) every tick is seen, and on a card running on its own those read
 * (`ticks_seen` of `ticks`; the peaks then come from consecutive ticks only). Lengths in
 * mm, the programmed path taken from the program (splines as fine polylines).
 */
typedef struct mc_path_report {
  /**
   * Seconds from the last tick at rest before the motion to the first at rest after it.
   */
  double path_time;
  /**
   * Motion blocks of the program so far (lines and arcs, rapids included; an arc with P
   * turns counts one a turn; a spline its polyline).
   */
  uint64_t segments;
  /**
   * The worst axis's peak commanded velocity over its path limit
   * (`mc_group_configure_path`'s `vmax`; an axis with none counts 0).
   */
  double peak_velocity_ratio;
  /**
   * The same for acceleration (`amax`).
   */
  double peak_acceleration_ratio;
  /**
   * The same for jerk (`jmax`).
   */
  double peak_jerk_ratio;
  /**
   * The largest distance from a commanded point to the programmed path, mm.
   */
  double max_deviation;
  /**
   * The largest distance from an actual point (the encoders) to the programmed path, mm:
   * the contour error.
   */
  double max_contour_error;
  /**
   * The largest distance between the commanded and the actual point of one tick, mm.
   */
  double max_following_error;
  /**
   * Stops between the first and the last move (dwells count).
   */
  uint64_t exact_stops;
  /**
   * Ticks from the first sample to the last.
   */
  uint64_t ticks;
  /**
   * Of them, the ticks sampled.
   */
  uint64_t ticks_seen;
} mc_path_report;

/**
 * A group's configuration (`mc_group_configure`). Start from `mc_group_settings_new`.
 */
typedef struct mc_group_settings {
  /**
   * Card axes of the group's X, Y, Z, … axes; the first `naxes` are used.
   */
  uint32_t axes[8];
  /**
   * Axes in the group, 1..8.
   */
  uint32_t naxes;
  /**
   * `MC_GROUP_ACCDEC_` value.
   */
  uint32_t accdec;
  /**
   * `MC_GROUP_INTERP_` value.
   */
  uint32_t interpolator;
  /**
   * Geometry tolerance (centre equidistance, radius against chord), in user units of the
   * group's first axis.
   */
  double tolerance;
  /**
   * Layout 1.11: stages in the group's home order (0: none configured), 0..8; what
   * `mc_group_home` with no stages runs.
   */
  uint32_t home_stages;
  /**
   * Stage k's group axes (the first `home_stages` are used), a mask: bit i is group axis i
   * (0: the group's X). `{1 << 2, 1 << 0 | 1 << 1}`: Z first, then X and Y together.
   */
  uint32_t home_order[8];
} mc_group_settings;

/**
 * A group move started by `mc_group_move_linear`, `_ptp`, `_circular`, `_nurbs`,
 * `mc_group_halt` or `mc_group_stop`; wait for it with `mc_group_motion_wait`.
 */
typedef struct mc_group_motion {
  /**
   * The group.
   */
  uint32_t group;
  /**
   * The seq of the command that started it (`MC_EVENT_GROUP_` events carry the same seq).
   */
  uint32_t seq;
} mc_group_motion;

/**
 * Limits of the tangential feed of a group move, in user units of the group's first axis.
 * Every value must be finite and greater than zero.
 */
typedef struct mc_path_limits {
  /**
   * Feed (path velocity).
   */
  double velocity;
  /**
   * Tangential acceleration.
   */
  double acceleration;
  /**
   * Tangential deceleration.
   */
  double deceleration;
  /**
   * Tangential jerk.
   */
  double jerk;
} mc_path_limits;

/**
 * How a group move is queued. All zero (`{0}`) is the default: absolute targets, the group
 * must be at rest, cutting feed.
 */
typedef struct mc_move_options {
  /**
   * Non-zero: targets relative to where the previous move ends.
   */
  uint32_t relative;
  /**
   * Non-zero: queue behind the moves already queued (PLCopen Buffered); else the group
   * must be at rest.
   */
  uint32_t buffered;
  /**
   * `MC_FEED_TYPE_` value.
   */
  uint32_t feed_type;
} mc_move_options;

/**
 * An arc in the coordinates of its plane (user units): the end point, and per `mode`
 * (`MC_ARC_BY_`) the centre, the radius (`aux[0]`) or a point on the arc.
 */
typedef struct mc_arc {
  /**
   * `MC_ARC_BY_` value.
   */
  uint32_t mode;
  /**
   * Non-zero: counter-clockwise; zero: clockwise (ignored by `MC_ARC_BY_BORDER`).
   */
  uint32_t ccw;
  /**
   * End point.
   */
  double end[2];
  /**
   * The centre (`MC_ARC_BY_CENTRE`), the radius in `aux[0]` (`MC_ARC_BY_RADIUS`), or a
   * point on the arc (`MC_ARC_BY_BORDER`).
   */
  double aux[2];
} mc_arc;

/**
 * Layout 1.13: an arc in the plane of three group axes given by a normal vector, for
 * `mc_group_move_circular_normal`: counter-clockwise about `normal` (any length but 0; the
 * right-hand rule) in the plane through the start, around `centre` to `end` (on `axes`, in
 * their user units; an end at the start: a full turn), then `turns` more full turns. `rise`
 * non-zero: the end may lie off the plane along the normal (a helix along it).
 */
typedef struct mc_normal_arc {
  /**
   * The plane's group axes a, b, c.
   */
  uint32_t axes[3];
  /**
   * The normal on them.
   */
  double normal[3];
  /**
   * The centre on a, b, c.
   */
  double centre[3];
  /**
   * The end on a, b, c.
   */
  double end[3];
  /**
   * Non-zero: the end may rise off the plane along the normal.
   */
  uint32_t rise;
  /**
   * Full turns added to the arc.
   */
  uint32_t turns;
} mc_normal_arc;

/**
 * How a NURBS curve is followed, in user units of the group's first axis.
 */
typedef struct mc_nurbs_feed {
  /**
   * Feed along the curve.
   */
  double feed;
  /**
   * Tangential acceleration limit.
   */
  double accel;
  /**
   * Tangential jerk limit.
   */
  double jerk;
  /**
   * Chord error tolerance (the feed is lowered where the curvature needs it), in the user
   * units of the group's first axis; 0: the default, one encoder count (1 µm on a 1 µm/count
   * scale).
   */
  double chord_tolerance;
  /**
   * Saturation-aware feed (Yeh §3.4): the fraction of each axis's PD+ `umax` the look-ahead
   * may plan with, in (0, 1]; needs PD+ on every group axis (`MC_ERR_INCOMPATIBLE_MODE`
   * otherwise). 0: not saturation-aware.
   */
  double saturation_budget;
} mc_nurbs_feed;

/**
 * One NURBS curve of a path (`mc_group_move_nurbs_path`), described as the arguments of
 * `mc_group_move_nurbs`: `n_ctrl` control points of `dim` values in `ctrl`, `n_ctrl` weights,
 * `n_knots` knots. The arrays are read during the call only.
 */
typedef struct mc_nurbs_curve {
  /**
   * Degree, 1..5.
   */
  uint32_t degree;
  /**
   * Dimension: the group's axis count.
   */
  uint32_t dim;
  /**
   * `n_ctrl * dim` doubles, point after point, in group axis order and user units.
   */
  const double *ctrl;
  /**
   * Control points.
   */
  size_t n_ctrl;
  /**
   * `n_ctrl` weights, finite and positive.
   */
  const double *weights;
  /**
   * `n_knots` knots, clamped and non-decreasing.
   */
  const double *knots;
  /**
   * `n_ctrl + degree + 1`.
   */
  size_t n_knots;
} mc_nurbs_curve;

/**
 * A consistent snapshot of a group's status. Path quantities are in counts of the group's
 * first axis (no scale applied), as the card publishes them.
 */
typedef struct mc_group_status {
  /**
   * `MC_GROUP_STATE_` value.
   */
  uint32_t state;
  /**
   * Moves waiting in the queue.
   */
  uint32_t queued;
  /**
   * Seq of the move being interpolated (0: none).
   */
  uint32_t active_seq;
  /**
   * Group moves started since boot.
   */
  uint32_t move_count;
  /**
   * Distance along the active move, counts.
   */
  double path_pos;
  /**
   * Length of the active move, counts.
   */
  double path_len;
  /**
   * Tangential velocity before the filters, counts/s.
   */
  double feed;
  /**
   * Tangential acceleration before the filters, counts/s².
   */
  double feed_acc;
  /**
   * Servo tick of this snapshot.
   */
  uint64_t tick;
  /**
   * At the group's last coming to rest, the largest |programmed end − commanded position|
   * over its axes: the correction its snap to the end made, counts (what the interpolation
   * and the filters lost, plus the rounding of the sums).
   */
  double snap_last;
  /**
   * The largest `snap_last` since the group was enabled, counts.
   */
  double snap_max;
  /**
   * Segments in the group's path buffer not finished yet (`mc_group_path_push`).
   */
  uint32_t path_queued;
  /**
   * Free segments in the path buffer (`MC_PATH_SEGMENTS` - `path_queued`).
   */
  uint32_t path_free;
  /**
   * Id of the segment running (valid while `path_flags` has `MC_PATH_STATUS_RUNNING`).
   */
  uint32_t path_id;
  /**
   * `MC_PATH_STATUS_` bits.
   */
  uint32_t path_flags;
  /**
   * Path segments ended since the group's last `mc_group_enable` (wrapping): 0 after each
   * enable, whatever ran before it (a disable keeps the count until the next enable; a
   * program that opens the card finds the count of the enable before it).
   */
  uint32_t path_done;
} mc_group_status;

/**
 * One acc/dec filter: kind and time constant.
 */
typedef struct mc_filter {
  /**
   * `MC_FILTER_KIND_` value.
   */
  uint32_t kind;
  /**
   * Time constant, s.
   */
  double tau;
} mc_filter;

/**
 * An axis's post-interpolation acc/dec filters, one per feed type.
 */
typedef struct mc_filter_settings {
  /**
   * Rapid traverse (`MC_FEED_TYPE_RAPID`).
   */
  struct mc_filter rapid;
  /**
   * Cutting feed (`MC_FEED_TYPE_CUTTING`).
   */
  struct mc_filter cutting;
  /**
   * Jog (`MC_FEED_TYPE_JOG`).
   */
  struct mc_filter jog;
} mc_filter_settings;

/**
 * The PD+ law (Yeh eq 2.12): u = kp e + kd de/dt + kv v_ref + ka a_ref (volts, counts, s).
 */
typedef struct mc_pdplus_gains {
  /**
   * V/count.
   */
  double kp;
  /**
   * V per count/s.
   */
  double kd;
  /**
   * V per count/s of reference velocity.
   */
  double kv;
  /**
   * V per count/s^2 of reference acceleration.
   */
  double ka;
} mc_pdplus_gains;

/**
 * The first-order drive model (Yeh eq 2.1-2.2 as corrected): dw/dt = -w/tau + (kc/tau) u,
 * dtheta/dt = ke w.
 */
typedef struct mc_drive_model {
  /**
   * Electrical gain K_c: steady motor speed per volt, (rad/s)/V.
   */
  double kc;
  /**
   * Mechanical time constant, s.
   */
  double tau;
  /**
   * Mechanical gain K_e, counts/rad.
   */
  double ke;
} mc_drive_model;

/**
 * An axis's PD+ law and drive model. Host writes; read with axis_config on
 * MC_OP_APPLY_AXIS_CONFIG when its servo_law is MC_SERVO_PDPLUS. The model predicts u for the
 * saturation-aware feed.
 */
typedef struct mc_axis_pdplus {
  /**
   * The PD+ gains.
   */
  struct mc_pdplus_gains gains;
  /**
   * The drive model.
   */
  struct mc_drive_model drive;
  /**
   * Drive limit, V (at most the DAC limit).
   */
  double umax;
  double _reserved[8];
} mc_axis_pdplus;

/**
 * The PD+ servo law of an axis (Yeh eq 2.12) and its drive model (Yeh eq 2.2), in counts,
 * seconds and volts: the card's `mc_axis_pdplus` register block, the same struct as in the
 * register map (`gains`: `u = kp·e + kd·ė + kv·v_ref + ka·a_ref`; `drive`: `dw/dt = −w/tau +
 * (kc/tau)·u`, `dθ/dt = ke·w`; `umax`, at most the axis's `dac_limit_v`).
 */
typedef struct mc_axis_pdplus mc_pdplus_settings;

/**
 * An axis's homing configuration (layout 1.5; see MC_OP_HOME). Host writes; the card validates
 * and copies it on MC_OP_APPLY_AXIS_HOMING. Counts and seconds.
 */
typedef struct mc_axis_homing {
  /**
   * CiA 402 homing method: 1..14, 17..30, 33, 34, 35, 37, or -1..-4 (hard stop).
   */
  int32_t method;
  /**
   * MC_HOMING_* bits.
   */
  uint32_t flags;
  /**
   * Velocity of the search for the switch, counts/s (> 0).
   */
  double search_vel;
  /**
   * Velocity of the final approach to the edge, the index or the hard stop, counts/s
   * (0 < creep_vel <= search_vel): how far the axis moves in a servo tick there is the
   * resolution of a switch edge.
   */
  double creep_vel;
  /**
   * Acceleration and deceleration, counts/s^2 (> 0).
   */
  double accel;
  /**
   * Jerk, counts/s^3 (> 0).
   */
  double jerk;
  /**
   * The home point reads MC_OP_HOME's position + home_offset, counts.
   */
  double home_offset;
  /**
   * The whole homing ends within this, s (0 < timeout <= MC_MAX_MOVE_TIME), else
   * MC_HOMING_ERROR_TIMEOUT.
   */
  double timeout;
  /**
   * The farthest the axis goes from where homing began, counts (> 0), else
   * MC_HOMING_ERROR_DISTANCE.
   */
  double max_distance;
  /**
   * The farthest the index pulse may be beyond the edge or hard stop, counts (> 0; a
   * revolution and a margin), else MC_HOMING_ERROR_NO_INDEX. Also the limit of methods 33, 34.
   */
  double index_distance;
  /**
   * Hard stop: the following error that means the axis stalled, counts (> 0; with the creep
   * velocity's share of hard_stop_dwell, under the axis's following-error limit at the creep
   * velocity, else MC_OP_HOME is refused with MC_NACK_BAD_CONFIG).
   */
  double hard_stop_ferror;
  /**
   * Hard stop: how long the following error stays at or above hard_stop_ferror, s (0..10).
   */
  double hard_stop_dwell;
  double _reserved[5];
} mc_axis_homing;

/**
 * An axis's homing configuration, in counts and seconds: the card's `mc_axis_homing` register
 * block, the same struct as in the register map. Start from `mc_homing_settings_default`.
 * `method` is a CiA 402 homing method: 1..14 (a limit or home switch, then the index pulse),
 * 17..30 (the same, the switch edge itself), 33, 34 (the next index pulse, negative or
 * positive), 35, 37 (the current position), or `MC_HOMING_METHOD_HARD_STOP_` (-1..-4);
 * `flags` are `MC_HOMING_FLAG_` bits. The home point reads `mc_home`'s position plus
 * `home_offset`.
 */
typedef struct mc_axis_homing mc_homing_settings;

/**
 * The digital inputs' configuration (layout 1.7). Host writes; the card validates and copies
 * it on MC_OP_APPLY_IO_CONFIG. All zero at boot: active high, no debounce, no events.
 */
typedef struct mc_io_config {
  /**
   * Bit i: input i is active low (the card inverts it).
   */
  uint32_t polarity;
  /**
   * Bit i: MC_EVENT_INPUT when debounced input i becomes active.
   */
  uint32_t rise_events;
  /**
   * Bit i: MC_EVENT_INPUT when debounced input i becomes inactive.
   */
  uint32_t fall_events;
  uint32_t _reserved0;
  /**
   * Ticks input i must hold a new level before the debounced word takes it
   * (0..MC_DEBOUNCE_MAX; 0: at once).
   */
  uint16_t debounce[16];
  uint32_t _reserved[4];
} mc_io_config;

/**
 * The digital inputs' configuration: the card's `mc_io_config` register block. `polarity`
 * bit i: input i is active low; `rise_events` / `fall_events` bit i: an `MC_EVENT_INPUT` on
 * that debounced edge of input i; `debounce[i]`: the ticks input i must hold a new level
 * before the debounced word takes it (0..10000). Start from `mc_io_settings_default`.
 */
typedef struct mc_io_config mc_io_settings;

/**
 * A compare channel's status (`mc_compare_get_status`), positions in the axis's user units.
 */
typedef struct mc_compare_info {
  /**
   * `MC_IO_STATE_` value.
   */
  uint32_t state;
  /**
   * Pulses fired since the arm.
   */
  uint32_t fires;
  /**
   * Positions missed since the arm.
   */
  uint32_t missed;
  /**
   * Positions still to come (a table's queue).
   */
  uint32_t pending;
  /**
   * The output pulsed.
   */
  uint32_t output;
  /**
   * The next position.
   */
  double next;
  /**
   * The last position fired.
   */
  double last_fired;
  /**
   * When: servo ticks since boot, with the fraction within the tick.
   */
  double last_fire_tick;
  /**
   * The last position missed.
   */
  double last_missed;
} mc_compare_info;

/**
 * What a touch probe captures at (`mc_touch_probe`).
 */
typedef struct mc_probe_trigger {
  /**
   * The input (0..15), or `MC_PROBE_INPUT_INDEX`.
   */
  uint32_t input;
  /**
   * `MC_PROBE_EDGE_` bits (one or both).
   */
  uint32_t edges;
  /**
   * Nonzero: keep capturing (the last `MC_PROBE_QUEUE` in the status); 0: one capture.
   */
  uint32_t continuous;
  /**
   * Nonzero: only edges with the position in `[window_lo, window_hi]` count.
   */
  uint32_t use_window;
  /**
   * The window, user units.
   */
  double window_lo;
  /**
   * The window, user units.
   */
  double window_hi;
  /**
   * Nonzero: the capture halts the axis's motion, by the card in the tick it sees it (its
   * group along the path on the members' stop ramps, or the axis on its stop ramp; stop
   * reason `MC_STOP_REASON_PROBE`): a probing move.
   */
  uint32_t halt;
} mc_probe_trigger;

/**
 * A touch probe's status (`mc_probe_get_status`), positions in user units.
 */
typedef struct mc_probe_info {
  /**
   * `MC_IO_STATE_` value.
   */
  uint32_t state;
  /**
   * Captures since the arm.
   */
  uint32_t captures;
  /**
   * Edges outside the window since the arm.
   */
  uint32_t outside;
  /**
   * How many of `positions` hold captures (up to `MC_PROBE_QUEUE`).
   */
  uint32_t count;
  /**
   * The last captures, oldest first.
   */
  double positions[8];
  /**
   * When the last capture was: servo ticks since boot, with the fraction.
   */
  double last_tick;
} mc_probe_info;

/**
 * One card found by `mc_list_cards`. Strings are NUL-terminated (cut to fit, at a character
 * boundary).
 */
typedef struct mc_card_listing {
  /**
   * The URI that opens it: `emu:NAME`, `uio:/dev/uioN` or `pci:DDDD:BB:DD.F`.
   */
  char uri[128];
  /**
   * Its name (`card-emu --name`, the board's EEPROM name); when the card could not be read,
   * the `emu:` socket's name or the UIO device's sysfs name.
   */
  char name[128];
  /**
   * The board's serial number (0: none, or not read).
   */
  uint64_t serial;
  /**
   * Axes on the card (0: not read).
   */
  uint32_t axes;
  /**
   * Servo rate, Hz (0: not read).
   */
  uint32_t servo_rate_hz;
  /**
   * Firmware version, `major << 16 | minor << 8 | patch` (0: not read).
   */
  uint32_t firmware_version;
  /**
   * DPRAM layout major version (0: not read).
   */
  uint16_t layout_major;
  /**
   * DPRAM layout minor version.
   */
  uint16_t layout_minor;
  /**
   * `MC_BUS_ALONE`, `MC_BUS_MASTER` or `MC_BUS_FOLLOWER`.
   */
  uint32_t sync_role;
  /**
   * `MC_BUSST_FREE`, `MC_BUSST_LOCKED` or `MC_BUSST_LOST`.
   */
  uint32_t sync_state;
  /**
   * A follower's master's name (empty otherwise).
   */
  char master[32];
  /**
   * 1: no host holds it, `mc_open` would get it now; 0: held (or not read).
   */
  uint32_t available;
  /**
   * 1: this process has it open.
   */
  uint32_t open_here;
  /**
   * `MC_OK`: every field was read from the card; else why it could not be read
   * (`MC_ERR_PERMISSION_DENIED`: the card's server refused this user; `MC_ERR_PROTOCOL`: a
   * card-emu of another release; ...), with `error_message`.
   */
  mc_result error;
  /**
   * What `error` means here, and what to do about it (empty with `MC_OK`).
   */
  char error_message[256];
} mc_card_listing;

/**
 * Limits of velocity mode, in user units (see `mc_set_scale`); each finite and > 0.
 */
typedef struct mc_velocity_limits {
  /**
   * Acceleration (speeding up).
   */
  double acceleration;
  /**
   * Deceleration (slowing down).
   */
  double deceleration;
  /**
   * Jerk.
   */
  double jerk;
} mc_velocity_limits;

/**
 * A group's path configuration (`mc_group_configure_path`), in user units: `vmax`, `amax`,
 * `jmax` per group axis (the first `naxes`, in group order, each in its axis's units);
 * `accel` and `jerk` tangential, in the first axis's units. Start from
 * `mc_path_settings_uniform`.
 */
typedef struct mc_path_settings {
  /**
   * Axes in the group: how many values of `vmax`, `amax`, `jmax` are used.
   */
  uint32_t naxes;
  /**
   * Checked (1..`MC_PATH_SEGMENTS`) and kept by the card; it looks ahead by distance, over
   * as many queued segments as braking from its speed takes, not this many.
   */
  uint32_t lookahead;
  /**
   * `MC_EVENT_PATH_LOW_WATER` when the segments queued fall to this (0: never).
   */
  uint32_t low_water;
  /**
   * Tangential acceleration limit (0: from the axes' limits).
   */
  double accel;
  /**
   * Tangential jerk limit (0: from the axes' limits).
   */
  double jerk;
  /**
   * Each axis's velocity limit (> 0).
   */
  double vmax[8];
  /**
   * Each axis's acceleration limit (> 0).
   */
  double amax[8];
  /**
   * Each axis's jerk limit (> 0).
   */
  double jmax[8];
  /**
   * The card's path planner period, s (0: its default, 1 ms; at most 10 ms), rounded to
   * whole servo ticks: the look-ahead and the speed planner run once a period, every servo
   * tick in between follows the jerk-limited profile they chose.
   */
  double plan_period;
  /**
   * Nonzero: `mc_group_path_stream` sends runs of lines that sample a smooth curve as that
   * curve, a cubic B-spline fitted within their tolerance (kept by the library, not the
   * card; a run sent as one curve reports the id of its last line). 0: every line as it is.
   */
  uint32_t chord_fit;
} mc_path_settings;

/**
 * One item of a path: a segment (`MC_SEGMENT_LINE`, `_ARC`, `_NURBS`, `_DWELL`) or an output
 * action (`MC_SEGMENT_OUTPUT`). Each kind reads only its own fields (listed with them); start
 * from `mc_path_segment_line`, `_arc`, `_nurbs`, `_dwell` or `_output`.
 */
typedef struct mc_path_segment {
  /**
   * `MC_SEGMENT_` value.
   */
  uint32_t kind;
  /**
   * Segments: the user's id, reported by `MC_EVENT_SEGMENT_START` / `_END` and in
   * `mc_group_status.path_id`.
   */
  uint32_t id;
  /**
   * Lines and arcs: the path speed (> 0), user units of the first group axis per second.
   */
  double feed;
  /**
   * Lines and arcs: `MC_PATH_BUFFER_` value.
   */
  uint32_t buffer;
  /**
   * Lines and arcs: `MC_PATH_TRANSITION_` value (used by the blending buffer modes).
   */
  uint32_t transition;
  /**
   * Lines and arcs: the blend's size for `transition` (>= 0), user units of the first axis.
   */
  double tolerance;
  /**
   * Lines and arcs: non-zero for targets (and arc points) relative to where the segment
   * before ends.
   */
  uint32_t relative;
  /**
   * Segments: non-zero on the last segment of a program (its stop is the end, not
   * starvation: no `MC_EVENT_PATH_STARVED`).
   */
  uint32_t last;
  /**
   * Lines and arcs: how many values of `target` are used.
   */
  uint32_t naxes;
  /**
   * Arcs: `MC_ARC_PLANE_` value.
   */
  uint32_t plane;
  /**
   * Lines: the end point, one value per group axis in group order. Arcs: the targets of the
   * group's other axes in group order (a helix), or none (`naxes` 0).
   */
  double target[8];
  /**
   * Arcs: the arc in its plane's coordinates.
   */
  struct mc_arc arc;
  /**
   * Dwells: the wait, seconds.
   */
  double seconds;
  /**
   * Output actions: the output, 0..`MC_CARD_OUTPUTS` - 1.
   */
  uint32_t output;
  /**
   * Output actions: non-zero sets the output, zero clears it.
   */
  uint32_t on;
  /**
   * Output actions: `MC_OUTPUT_AT_` value.
   */
  uint32_t at;
  /**
   * Output actions with `MC_OUTPUT_AT_DISTANCE`: the distance into the segment.
   */
  double distance;
  /**
   * NURBS curves: the curve (its arrays read while the item is queued).
   */
  struct mc_nurbs_curve curve;
  /**
   * NURBS curves: the largest distance of the path from the curve (> 0).
   */
  double fit_tolerance;
  /**
   * Normal-vector arcs (layout 1.12): the plane's three group axes.
   */
  uint32_t plane_axes[3];
  /**
   * Normal-vector arcs: the normal on them (any length but 0).
   */
  double normal[3];
  /**
   * Normal-vector arcs: the centre on the three axes.
   */
  double centre[3];
  /**
   * Normal-vector arcs: the end on the three axes.
   */
  double end[3];
  /**
   * Normal-vector arcs: non-zero lets the end lie off the plane along the normal.
   */
  uint32_t rise;
} mc_path_segment;

/**
 * How far `mc_group_path_stream` has come (given to its progress callback).
 */
typedef struct mc_path_progress {
  /**
   * Items sent to the card.
   */
  uint64_t sent;
  /**
   * Items the card accepted (it lags `sent` by the commands in flight).
   */
  uint64_t accepted;
  /**
   * Segments the card finished since the group was enabled (wrapping).
   */
  uint32_t done;
  /**
   * Segments queued on the card.
   */
  uint32_t queued;
} mc_path_progress;

/**
 * The progress callback of `mc_group_path_stream`: called on the calling thread, inside
 * `mc_group_path_stream`, after each item is sent. `progress` is valid only during the call;
 * `user` is the pointer given to `mc_group_path_stream`. It must return (not unwind or
 * longjmp out of the library).
 */
typedef void (*mc_path_progress_callback)(const struct mc_path_progress *progress, void *user);

/**
 * A path stream running in a thread of the library (`mc_group_path_stream_start`): an
 * integer handle, never 0, valid until `mc_path_streamer_join`.
 */
typedef uint32_t mc_path_streamer;

/**
 * A stream's limits, user units: every segment's velocity and acceleration stay within them.
 */
typedef struct mc_pvt_limits {
  /**
   * Velocity.
   */
  double velocity;
  /**
   * Acceleration.
   */
  double acceleration;
} mc_pvt_limits;

/**
 * One point, user units: seconds from the start of the stream, position, velocity (PVT).
 */
typedef struct mc_pvt_point {
  /**
   * Seconds from the start of the stream.
   */
  double time;
  /**
   * Position.
   */
  double position;
  /**
   * Velocity (ignored in PT).
   */
  double velocity;
} mc_pvt_point;

/**
 * The card-wide safety state (`mc_get_safety_status`). Flags are 0 or 1.
 */
typedef struct mc_safety_status {
  /**
   * The host watchdog tripped; latched until `mc_reset_faults`.
   */
  uint32_t watchdog_tripped;
  /**
   * The host's e-stop (`mc_estop`) is latched.
   */
  uint32_t estop_command;
  /**
   * The e-stop input tripped; latched until reset with the input released.
   */
  uint32_t estop_input;
  /**
   * The watchdog is watching: a session is attached (armed by its open, disarmed by its
   * close). Outside a session the card takes no motion (`MC_ERR_NO_SESSION`).
   */
  uint32_t watchdog_armed;
  /**
   * Servo tick at which the card last saw the heartbeat change.
   */
  uint64_t last_heartbeat_tick;
  /**
   * Servo tick of the last watchdog trip (0: never).
   */
  uint64_t watchdog_trip_tick;
  /**
   * The tick of the last heartbeat the card saw before that trip.
   */
  uint64_t trip_heartbeat_tick;
  /**
   * Protocol errors (corrupt ring indices) the card detected since boot.
   */
  uint32_t protocol_errors;
  /**
   * The session id of the program attached to the card (this one's while it is open).
   */
  uint32_t session;
  /**
   * Programs that opened the card while another's session was still open, since boot (each
   * stopped the motion the vanished program left).
   */
  uint32_t host_changes;
  /**
   * Heartbeats that came later than the declared period after the one before, since this
   * program opened the card: how close it runs to its watchdog.
   */
  uint32_t late_heartbeats;
  /**
   * The longest gap between two heartbeats the card saw since this program opened it, µs.
   */
  uint32_t max_heartbeat_gap_us;
  /**
   * Servo tick of the last open (this program's, while it is open).
   */
  uint64_t attach_tick;
} mc_safety_status;

/**
 * An axis's safety configuration (`mc_configure_safety`), in user units (see `mc_set_scale`).
 * Start from `mc_safety_settings_default`. Flags: non-zero is on.
 */
typedef struct mc_safety_settings {
  /**
   * Enforce `soft_limit_neg` .. `soft_limit_pos` (off by default).
   */
  uint32_t soft_limits;
  /**
   * Honour the limit switch inputs.
   */
  uint32_t hard_limits;
  /**
   * Honour the amplifier alarm input.
   */
  uint32_t amp_alarm;
  /**
   * Honour encoder loss and jumps.
   */
  uint32_t encoder_checks;
  /**
   * The stop a hard or soft limit makes (`MC_STOP_CATEGORY_`).
   */
  uint32_t limit_stop;
  /**
   * Negative soft limit (used when `soft_limits` is on; 0 in the defaults).
   */
  double soft_limit_neg;
  /**
   * Positive soft limit (used when `soft_limits` is on; 0 in the defaults).
   */
  double soft_limit_pos;
  /**
   * Following-error limit at `max_velocity` (LinuxCNC FERROR); the limit at velocity v is
   * `max(ferror * |v| / max_velocity, min_ferror)`.
   */
  double ferror;
  /**
   * Following-error limit at rest (LinuxCNC MIN_FERROR).
   */
  double min_ferror;
  /**
   * The velocity `ferror` applies at.
   */
  double max_velocity;
  /**
   * Deceleration of category 1 and 2 stops.
   */
  double stop_deceleration;
  /**
   * Jerk of those stops.
   */
  double stop_jerk;
  /**
   * Fastest physically possible encoder velocity: a larger change in one tick is a fault.
   */
  double encoder_max_velocity;
} mc_safety_settings;

/**
 * How an axis's last safety stop went, measured by the card (`mc_get_stop_info`).
 */
typedef struct mc_stop_info {
  /**
   * Why the last motion ended (`MC_STOP_REASON_` value).
   */
  uint32_t reason;
  /**
   * 1 when the axis has come to rest after its last safety stop (`rest_tick` is valid), 0
   * while it is still stopping or when there was none.
   */
  uint32_t at_rest;
  /**
   * Servo tick at which the last safety stop began (0: none since boot).
   */
  uint64_t stop_tick;
  /**
   * Servo tick at which the axis came to rest after it (0 while still stopping).
   */
  uint64_t rest_tick;
  /**
   * Planned duration of the stop's deceleration ramp, s (0 for category 0).
   */
  double ramp_time;
} mc_stop_info;

/**
 * The scope's configuration (layout 1.8). Host writes; the card validates and copies it on
 * MC_OP_SCOPE_CONFIGURE. All zero at boot (n_channels 0: not configured).
 */
typedef struct mc_scope_config {
  /**
   * Channels sampled, 1..MC_SCOPE_CHANNELS.
   */
  uint32_t n_channels;
  /**
   * A sample every divider ticks, 1..MC_SCOPE_DIVIDER_MAX.
   */
  uint32_t divider;
  /**
   * Channel k's source, MC_SCOPE_SOURCE(MC_SCOPE_SIG_*, index).
   */
  uint32_t source[16];
  /**
   * MC_SCOPE_ONE_SHOT or MC_SCOPE_CONTINUOUS.
   */
  uint32_t mode;
  /**
   * MC_SCOPE_TRIG_*.
   */
  uint32_t trigger;
  /**
   * MC_SCOPE_TRIG_LEVEL: the channel compared with level.
   */
  uint32_t trigger_channel;
  /**
   * MC_SCOPE_TRIG_INPUT: the input, 0..MC_CARD_INPUTS-1.
   */
  uint32_t trigger_input;
  /**
   * MC_SCOPE_RISING, _FALLING or _EITHER (level and input triggers).
   */
  uint32_t edge;
  /**
   * Samples kept from before the trigger, 0..MC_SCOPE_PRETRIGGER_MAX.
   */
  uint32_t pre_trigger;
  /**
   * One-shot: samples from the trigger sample on, >= 1.
   */
  uint32_t post_trigger;
  uint32_t _reserved0;
  /**
   * MC_SCOPE_TRIG_LEVEL: the level, in the channel's unit.
   */
  double level;
  uint64_t _reserved[4];
} mc_scope_config;

/**
 * The scope's configuration: the card's `mc_scope_config` register block. `source[k]` is
 * channel k's signal: `MC_SCOPE_SIG_*` | index << 16 (the axis for axis signals, the group for
 * group signals, 0 for the card's); `n_channels` 1..16; `divider` 1..65536 (a sample every
 * `divider` servo ticks); `mode` `MC_SCOPE_ONE_SHOT` (then `post_trigger` samples from the
 * trigger sample on) or `MC_SCOPE_CONTINUOUS`; `trigger` `MC_SCOPE_TRIG_*` with
 * `trigger_channel` and `level` (level crossing), `trigger_input` (input edge) and `edge`
 * `MC_SCOPE_RISING`, `_FALLING`, `_EITHER`; `pre_trigger` 0..1024 samples from before the
 * trigger. Start from `mc_scope_settings_default`.
 */
typedef struct mc_scope_config mc_scope_settings;

/**
 * A scope ring entry (layout 1.8): one sample. Card writes.
 */
typedef struct mc_scope_sample {
  /**
   * The servo tick it was taken at.
   */
  uint64_t tick;
  /**
   * Channel k's value (channels >= n_channels: 0).
   */
  double value[16];
} mc_scope_sample;

/**
 * The scope's state (layout 1.8). Card writes; independent words, updated each tick the
 * scope runs and by its commands.
 */
typedef struct mc_scope_status {
  /**
   * MC_SCOPE_STATE_IDLE, _WAITING, _CAPTURING or _DONE.
   */
  uint32_t state;
  /**
   * The seq of the MC_OP_SCOPE_ARM of the capture.
   */
  uint32_t arm_seq;
  /**
   * Channels per sample of the capture.
   */
  uint32_t n_channels;
  /**
   * The divider of the capture.
   */
  uint32_t divider;
  /**
   * The trigger sample's servo tick (0: not triggered yet).
   */
  uint64_t trigger_tick;
  /**
   * Samples put in the ring since the arm.
   */
  uint64_t samples;
  /**
   * Samples lost since the arm (the ring was full).
   */
  uint64_t lost;
  /**
   * The pre-trigger samples the capture took, put in the ring (or lost) first: pre_trigger,
   * or fewer when the trigger came before that many samples were taken since the arm (0
   * until the trigger).
   */
  uint32_t pre_captured;
  uint32_t _reserved0;
  uint64_t _reserved[2];
} mc_scope_status;

/**
 * The scope's state: `state` `MC_SCOPE_STATE_*`, the arm's seq, the capture's channels and
 * divider, the trigger sample's tick (0: not yet), the samples put in the ring and lost since
 * the arm, and `pre_captured`: how many pre-trigger samples the capture took, first in the
 * ring (`pre_trigger`, or fewer when the trigger came before that many samples had been
 * taken since the arm; 0 until the trigger).
 */
typedef struct mc_scope_status mc_scope_info;

/**
 * The PID + feed-forward law (layout 1.11, Kim section 5): on the following error
 * e = x_ref - x (counts), u = kp e + I + kd de/dt (through a first-order filter at
 * d_filter_hz) + kvff v_ref + kaff a_ref + friction sign(v_ref) (0 while |v_ref| <= deadband).
 * I integrates ki e and is clamped (anti-windup) to the DAC limit; it stops integrating while
 * the output is saturated in the error's direction. Host writes; read with axis_config on
 * MC_OP_APPLY_AXIS_CONFIG when its servo_law is MC_SERVO_PIDFF (a switch to it at rest is
 * bumpless: the integrator starts from the output of the tick). Volts, counts, seconds.
 */
typedef struct mc_axis_pidff {
  /**
   * Proportional gain, V/count.
   */
  double kp;
  /**
   * Integral gain, V/(count s).
   */
  double ki;
  /**
   * Derivative gain, V per count/s.
   */
  double kd;
  /**
   * Velocity feed-forward, V per count/s of v_ref.
   */
  double kvff;
  /**
   * Acceleration feed-forward, V per count/s^2 of a_ref.
   */
  double kaff;
  /**
   * Coulomb friction feed-forward, V (times the sign of v_ref).
   */
  double friction;
  /**
   * |v_ref| at or below which the friction feed-forward is 0, counts/s (> 0).
   */
  double friction_deadband;
  /**
   * The derivative's first-order filter cut-off, Hz (> 0; at or above the Nyquist frequency
   * it filters next to nothing).
   */
  double d_filter_hz;
  double _reserved[8];
} mc_axis_pidff;

/**
 * The PID + feed-forward law of an axis (Kim §5), in counts, seconds and volts: the card's
 * `mc_axis_pidff` register block. `u = kp·e + ki·∫e + kd·ė + kvff·v_ref + kaff·a_ref +
 * friction·sgn(v_ref)`: e the following error, ė through a first-order filter at
 * `d_filter_hz`, the integrator clamped to the DAC limit (and stopped while the output is
 * saturated in e's direction), the friction term 0 while |v_ref| <= `friction_deadband`.
 */
typedef struct mc_axis_pidff mc_pidff_settings;

/**
 * One servo filter: `kind` (`MC_BIQUAD_NOTCH`, `_LOWPASS`, `_LEAD_LAG`, `_RAW`; read back,
 * `MC_BIQUAD_NONE` for an empty slot) and its parameters; the ones its kind does not use are
 * 0.
 */
typedef struct mc_servo_filter {
  /**
   * `MC_BIQUAD_*`.
   */
  uint32_t kind;
  uint32_t _reserved0;
  /**
   * Notch: the centre; low-pass: the corner; lead/lag: the zero's frequency, Hz.
   */
  double freq_hz;
  /**
   * Notch, low-pass: the damping ratio (a notch's width: its -3 dB band is about
   * 2·damping·freq_hz wide).
   */
  double damping;
  /**
   * Notch: the gain at the centre, dB (-120..0).
   */
  double depth_db;
  /**
   * Lead/lag: the pole's frequency, Hz.
   */
  double freq2_hz;
  /**
   * `MC_BIQUAD_RAW`: b0, b1, b2, a1, a2 (a0 = 1). Read back (every kind): the coefficients
   * the card designed at the servo rate.
   */
  double coeffs[5];
} mc_servo_filter;

/**
 * A path across cards' settings (`mc_set_path_open`), in user units: `vmax`, `amax`, `jmax`
 * per dimension (the first `ndims`, each in its axis's units); `accel` and `jerk` tangential,
 * in the first dimension's units. Start from `mc_set_path_settings_uniform`.
 */
typedef struct mc_set_path_settings {
  /**
   * Dimensions of the path (1..`MC_PATH_MAX_DIMS`): the axes of the parts' groups together.
   */
  uint32_t ndims;
  /**
   * Checked (1..`MC_PATH_SEGMENTS`) and kept by every card, as `mc_path_settings.lookahead`.
   */
  uint32_t lookahead;
  /**
   * `MC_EVENT_PATH_LOW_WATER` when the segments queued fall to this (0: never).
   */
  uint32_t low_water;
  /**
   * Tangential acceleration limit (0: from the dimensions' limits).
   */
  double accel;
  /**
   * Tangential jerk limit (0: from the dimensions' limits).
   */
  double jerk;
  /**
   * Each dimension's velocity limit (> 0).
   */
  double vmax[16];
  /**
   * Each dimension's acceleration limit (> 0).
   */
  double amax[16];
  /**
   * Each dimension's jerk limit (> 0).
   */
  double jmax[16];
  /**
   * The cards' path planner period, s (0: their default), as `mc_path_settings.plan_period`.
   */
  double plan_period;
} mc_set_path_settings;

/**
 * One card's part of a path across cards: group `group` of the card `cards[card]` of
 * `mc_set_path_open`.
 */
typedef struct mc_path_part {
  /**
   * The card: its index in the `cards` array.
   */
  uint32_t card;
  /**
   * Its group (configured and enabled, at rest, its path idle).
   */
  uint32_t group;
} mc_path_part;

/**
 * A path across the cards of one sync bus (`mc_set_path_open`): an integer handle, never 0,
 * valid until `mc_set_path_close`.
 */
typedef uint32_t mc_set_path;

/**
 * A card's name, serial and place on the sync bus.
 */
typedef struct mc_bus_status {
  /**
   * The card's name, NUL-terminated.
   */
  char name[32];
  /**
   * Its serial number (0: none).
   */
  uint64_t serial;
  /**
   * `MC_BUS_ALONE`, `MC_BUS_MASTER` or `MC_BUS_FOLLOWER`.
   */
  uint32_t role;
  /**
   * `MC_BUSST_FREE`, `MC_BUSST_LOCKED` or `MC_BUSST_LOST`.
   */
  uint32_t state;
  /**
   * A follower's master, NUL-terminated ("" otherwise).
   */
  char master[32];
  /**
   * A master's followers now.
   */
  uint32_t followers;
  /**
   * Timed commands held.
   */
  uint32_t timed_held;
  /**
   * The earliest held one's tick (0: none).
   */
  uint64_t timed_next;
  /**
   * Times it lost its master since boot.
   */
  uint32_t losses;
} mc_bus_status;

typedef struct mc_safety_config {
  uint32_t watchdog_timeout_us;
  uint32_t estop_input_category;
  uint32_t max_stop_time_us;
  uint32_t _reserved[13];
} mc_safety_config;

/**
 * The card-wide safety settings as the card holds them (`mc_get_card_safety`): the register
 * map's `mc_safety_config` block (watchdog timeout in µs, the e-stop input's stop category,
 * the maximum stop time in µs).
 */
typedef struct mc_safety_config mc_card_safety_settings;

/**
 * Success.
 */
#define MC_OK 0

/**
 * The URI is not one of `sim`, `emu:NAME`, `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`,
 * `name:NAME`, `serial:N`.
 */
#define MC_ERR_BAD_URI -1

/**
 * No card at that URI.
 */
#define MC_ERR_NOT_FOUND -2

/**
 * The card is open already: in another process, or in this one (a card is opened once
 * per process; the message says which).
 */
#define MC_ERR_BUSY -3

/**
 * The card's DPRAM layout major version differs from this library's.
 */
#define MC_ERR_VERSION_MISMATCH -4

/**
 * The card does not answer (its tick counter stopped, or it was removed).
 */
#define MC_ERR_NOT_RESPONDING -5

/**
 * The card broke the protocol (corrupt ring indices, bad signature, torn status).
 */
#define MC_ERR_PROTOCOL -6

/**
 * The command ring is full: nothing was queued.
 */
#define MC_ERR_RING_FULL -7

/**
 * A wait ran out of time.
 */
#define MC_ERR_TIMEOUT -8

/**
 * The motion waited for was aborted by another command or a fault.
 */
#define MC_ERR_ABORTED -9

/**
 * The card has no such axis.
 */
#define MC_ERR_BAD_AXIS -10

/**
 * An argument is NaN or infinite.
 */
#define MC_ERR_NOT_FINITE -11

/**
 * A limit is zero or negative.
 */
#define MC_ERR_NON_POSITIVE_LIMIT -12

/**
 * The axis is disabled.
 */
#define MC_ERR_AXIS_DISABLED -13

/**
 * The command is not allowed in the axis's current state.
 */
#define MC_ERR_INVALID_STATE -14

/**
 * A configuration value is out of range.
 */
#define MC_ERR_BAD_CONFIG -15

/**
 * No motion profile satisfies the request.
 */
#define MC_ERR_INFEASIBLE -16

/**
 * A position beyond the card's range, or a velocity beyond its own (a jog above `jog_max_vel`).
 */
#define MC_ERR_OUT_OF_RANGE -17

/**
 * The card configuration can only change while all axes are disabled.
 */
#define MC_ERR_AXES_ENABLED -18

/**
 * The firmware does not know the command.
 */
#define MC_ERR_UNKNOWN_COMMAND -19

/**
 * No such axes group.
 */
#define MC_ERR_BAD_GROUP -22

/**
 * An axis already belongs to another group.
 */
#define MC_ERR_AXIS_IN_OTHER_GROUP -23

/**
 * The move needs an axis the group does not have.
 */
#define MC_ERR_AXIS_NOT_IN_GROUP -24

/**
 * An axis of the group is moving on its own.
 */
#define MC_ERR_AXIS_BUSY -25

/**
 * Single-axis motion on an axis of an enabled group.
 */
#define MC_ERR_AXIS_GROUPED -26

/**
 * The arc has zero length or zero radius.
 */
#define MC_ERR_ZERO_LENGTH_ARC -27

/**
 * The centre is not equidistant from start and end within the tolerance.
 */
#define MC_ERR_CENTRE_NOT_EQUIDISTANT -28

/**
 * The radius is shorter than half the chord.
 */
#define MC_ERR_RADIUS_TOO_SMALL -29

/**
 * The three points of a border-point arc are on one line.
 */
#define MC_ERR_COLLINEAR_POINTS -30

/**
 * The group's move queue is full: nothing was queued.
 */
#define MC_ERR_QUEUE_FULL -31

/**
 * The interpolator cannot run with the group's acc/dec mode.
 */
#define MC_ERR_INCOMPATIBLE_MODE -32

/**
 * The group is disabled (or not configured).
 */
#define MC_ERR_GROUP_DISABLED -33

/**
 * Filters can change only while they hold no distance.
 */
#define MC_ERR_FILTER_BUSY -34

/**
 * NURBS data or end without a begin, out of order, or missing.
 */
#define MC_ERR_NURBS_SEQUENCE -35

/**
 * NURBS degree outside 1..5.
 */
#define MC_ERR_NURBS_DEGREE -36

/**
 * NURBS on a group of fewer than 2 axes.
 */
#define MC_ERR_NURBS_DIMENSION -37

/**
 * Too few or too many control points.
 */
#define MC_ERR_NURBS_CTRL_COUNT -38

/**
 * The knot count is not n_ctrl + degree + 1.
 */
#define MC_ERR_NURBS_KNOT_COUNT -39

/**
 * The knots decrease.
 */
#define MC_ERR_NURBS_KNOTS_DECREASING -40

/**
 * An interior knot is repeated more than degree times.
 */
#define MC_ERR_NURBS_KNOT_MULTIPLICITY -41

/**
 * The end knots are not repeated degree + 1 times (or the domain is empty).
 */
#define MC_ERR_NURBS_NOT_CLAMPED -42

/**
 * A weight is not finite and positive.
 */
#define MC_ERR_NURBS_WEIGHT -43

/**
 * A control point is not finite.
 */
#define MC_ERR_NURBS_POINT -44

/**
 * The curve does not start where the group's path is.
 */
#define MC_ERR_NURBS_START -45

/**
 * The curve has zero length.
 */
#define MC_ERR_NURBS_ZERO_LENGTH -46

/**
 * A knot is not finite.
 */
#define MC_ERR_NURBS_KNOT -54

/**
 * An operating-system call failed.
 */
#define MC_ERR_IO -20

/**
 * The backend cannot do this (for example interrupts on a `pci:` card).
 */
#define MC_ERR_UNSUPPORTED -21

/**
 * The host watchdog tripped and is latched: `mc_reset_faults` first.
 */
#define MC_ERR_WATCHDOG_TRIPPED -47

/**
 * An e-stop is latched: `mc_reset_faults` first.
 */
#define MC_ERR_ESTOP_ACTIVE -48

/**
 * The move would go further into an active limit switch.
 */
#define MC_ERR_HARD_LIMIT -49

/**
 * The move would go further beyond a soft limit.
 */
#define MC_ERR_SOFT_LIMIT -50

/**
 * A reset was refused because its cause (alarm, encoder fault, e-stop input, missing
 * heartbeat) is still present.
 */
#define MC_ERR_CAUSE_ACTIVE -51

/**
 * A watchdog timeout of zero or under 1.5 × the host's heartbeat period.
 */
#define MC_ERR_WATCHDOG_TIMEOUT -52

/**
 * A stop category other than 0, 1 or 2.
 */
#define MC_ERR_BAD_CATEGORY -53

/**
 * A kinematic limit outside the range the card accepts
 * (denormal, absurdly small or large).
 */
#define MC_ERR_LIMIT_RANGE -55

/**
 * The card planned a profile that failed its own check (shorter than |d|/vmax, off its
 * target or beyond a limit) and refused it: nothing moved.
 */
#define MC_ERR_PLAN_CHECK -56

/**
 * The card served the command after its deadline and refused it: it was not executed.
 */
#define MC_ERR_EXPIRED -57

/**
 * A stop ramp longer than the card's maximum stop time, or a maximum stop time out of
 * range.
 */
#define MC_ERR_STOP_TOO_LONG -58

/**
 * The card's session belongs to another host.
 */
#define MC_ERR_SESSION -59

/**
 * No host session is attached to the card (it was detached, for example by a raw
 * `MC_OP_HOST_DETACH`): the card refuses motion, power, outputs, configuration and
 * resets until a host attaches: close the card and open it again (a tool may send a raw
 * `MC_OP_HOST_ATTACH`). It still takes stops, reads and the scope.
 */
#define MC_ERR_NO_SESSION -108

/**
 * The card went away (its `card-emu` process exited or was killed): every call on it
 * fails with this.
 */
#define MC_ERR_CARD_GONE -60

/**
 * The card was closed (`mc_close`) while the call waited, or before it.
 */
#define MC_ERR_CLOSED -61

/**
 * The wait was cancelled from another thread (`mc_cancel_waits`).
 */
#define MC_ERR_CANCELLED -62

/**
 * The card's server refused this user (`emu:` access control).
 */
#define MC_ERR_PERMISSION_DENIED -63

/**
 * An override factor outside 0 to 2 (0 % to 200 %).
 */
#define MC_ERR_OVERRIDE_RANGE -64

/**
 * A homing method the axis cannot do: an unknown CiA 402 number, or an index method on an
 * encoder without an index channel (`mc_homing_settings`).
 */
#define MC_ERR_HOMING_METHOD -65

/**
 * A move, jog or homing on an axis that is homing: wait for it, or halt it first.
 */
#define MC_ERR_AXIS_HOMING -66

/**
 * Homing ended without a home point (its switch, hard stop or index was not found in
 * time or distance): the axis is at rest and not homed.
 */
#define MC_ERR_HOMING_FAILED -67

/**
 * A path segment's buffer mode or transition mode is not one the card knows.
 */
#define MC_ERR_PATH_MODE -68

/**
 * A path line of length zero.
 */
#define MC_ERR_PATH_ZERO_LENGTH -69

/**
 * An output number beyond the card's outputs, or too many output actions before a segment.
 */
#define MC_ERR_PATH_OUTPUT -70

/**
 * A path segment while group moves run, a group move while the path runs, or the path
 * configuration changed while it runs.
 */
#define MC_ERR_PATH_BUSY -71

/**
 * A segment id that is not an integer in 0..2^32-1.
 */
#define MC_ERR_PATH_ID -72

/**
 * A NURBS path segment with a point of zero tangent (a cusp: split the curve there), or
 * one needing more pieces than the path buffer holds (a looser fit tolerance, or split
 * the curve).
 */
#define MC_ERR_PATH_CURVE -73

/**
 * The digital inputs' configuration: an input beyond the card's 16, or a debounce over
 * 10,000 ticks (`mc_io_settings`).
 */
#define MC_ERR_IO_CONFIG -90

/**
 * A compare or probe channel the card does not have.
 */
#define MC_ERR_IO_CHANNEL -91

/**
 * A compare mode, direction, output, pulse width, low-water mark, pitch or count out of
 * its range.
 */
#define MC_ERR_COMPARE_MODE -92

/**
 * The compare channel's table has no room for the positions: wait for low water.
 */
#define MC_ERR_COMPARE_FULL -93

/**
 * Compare table positions must be strictly monotonic in the channel's direction.
 */
#define MC_ERR_COMPARE_ORDER -94

/**
 * The compare channel is armed (disarm it first), its table runs the other way, or its
 * output is another armed channel's.
 */
#define MC_ERR_COMPARE_BUSY -95

/**
 * A probe input beyond the inputs and the index, no edge, or a window whose low end is
 * above its high end.
 */
#define MC_ERR_PROBE_INPUT -96

/**
 * Layout 1.7 (sync): a gear ratio that is not an integer numerator over a positive
 * integer denominator, both of magnitude 1..2^31-1.
 */
#define MC_ERR_GEAR_RATIO -74

/**
 * A master the card does not have (axis or auxiliary encoder), the slave itself, an
 * unknown master source, or a master axis disabled or in ErrorStop.
 */
#define MC_ERR_SYNC_MASTER -75

/**
 * A PT/PVT point not at least one servo period after the point before it, or a segment
 * longer than the longest move.
 */
#define MC_ERR_PVT_TIME -76

/**
 * A PT/PVT point whose segment breaks the stream's velocity or acceleration limit (the
 * error names the point).
 */
#define MC_ERR_PVT_LIMIT -77

/**
 * PT/PVT commands out of sequence: points without an open stream or after its last point,
 * a start without points or on an axis that moved, a begin while a stream runs.
 */
#define MC_ERR_PVT_SEQUENCE -78

/**
 * A cam table number, point count or flags out of range, points not strictly increasing
 * in the master or not finite, a table not loaded, or one in use by a slave.
 */
#define MC_ERR_CAM_TABLE -79

/**
 * Cam table data without an open table or out of order.
 */
#define MC_ERR_CAM_SEQUENCE -80

/**
 * Layout 1.8: a scope signal the card does not know, or an axis or group it has not.
 */
#define MC_ERR_SCOPE_SIGNAL -81

/**
 * Scope channels 0 or more than 16.
 */
#define MC_ERR_SCOPE_CHANNELS -82

/**
 * A scope divider 0 or above 65536.
 */
#define MC_ERR_SCOPE_DIVIDER -83

/**
 * A bad scope mode, trigger, edge, trigger channel or input, a level not finite, or a
 * one-shot capture of no samples.
 */
#define MC_ERR_SCOPE_TRIGGER -84

/**
 * More pre-trigger samples than the card keeps.
 */
#define MC_ERR_SCOPE_PRETRIGGER -85

/**
 * A scope command its state does not allow.
 */
#define MC_ERR_SCOPE_STATE -86

/**
 * Layout 1.8: a configuration read-back of a block kind the card does not know (a card
 * older than the library, or a kind or index that is not an integer).
 */
#define MC_ERR_CONFIG_KIND -106

/**
 * Layout 1.9: a compensation table's point count (over 256), bound (not > 0), backlash
 * (negative, or over twice the bound), ramp velocity or acceleration (outside the card's
 * range) out of range.
 */
#define MC_ERR_COMP_TABLE -110

/**
 * Compensation data without an open table, or out of order.
 */
#define MC_ERR_COMP_SEQUENCE -111

/**
 * Compensation positions that are not strictly increasing.
 */
#define MC_ERR_COMP_ORDER -112

/**
 * A correction (with half the backlash) beyond the table's bound, or a table of one
 * column whose reverse correction differs from its forward one.
 */
#define MC_ERR_COMP_BOUND -113

/**
 * A compensation table changed on an axis that is not at rest.
 */
#define MC_ERR_COMP_BUSY -114

/**
 * Layout 1.10: a modulo period of zero given to `set_modulo` (a period must be a positive
 * length; `clear_modulo` makes an axis linear).
 */
#define MC_ERR_MODULO_ZERO -116

/**
 * A modulo period that is negative, not finite, or outside the card's range (1 count to
 * 10^11 counts).
 */
#define MC_ERR_MODULO_RANGE -117

/**
 * A modulo period changed on an axis that is not at rest.
 */
#define MC_ERR_MODULO_BUSY -118

/**
 * An absolute move that does not fit the axis: on a modulo axis a target outside
 * [0, modulo), on a linear axis a direction other than the shortest way.
 */
#define MC_ERR_MODULO_MOVE -119

/**
 * Layout 1.10: a handwheel input the card does not have.
 */
#define MC_ERR_HANDWHEEL_INPUT -120

/**
 * A handwheel ratio of 0 or beyond the maximum (10000 counts per detent), or a detent
 * outside 1..=1024 auxiliary counts.
 */
#define MC_ERR_HANDWHEEL_RATIO -121

/**
 * A configuration file that does not parse, or a value in it that the card would refuse
 * (the error names the key and its line); nothing of the file was applied.
 */
#define MC_ERR_CONFIG_FILE -107

/**
 * A G-code program refused by the interpreter (the error names the line and what is
 * wrong there); nothing after that line was queued.
 */
#define MC_ERR_GCODE -109

/**
 * A wait for the last motion of an axis (or the last move of a group) when this library
 * has started none there since the card was opened: there is nothing to wait for (the
 * axis or group may still move, by motion of another kind: a raw command, another host).
 */
#define MC_ERR_NO_MOTION -115

/**
 * Layout 1.10: the axis is a slave of a formed gantry; it moves only with its master.
 */
#define MC_ERR_GANTRY_SLAVE -125

/**
 * A gantry member already in use: in another gantry, a slave in a group, geared, cammed
 * or streaming.
 */
#define MC_ERR_GANTRY_IN_USE -126

/**
 * A gantry's axes: an index, master or slave out of range, the master among its slaves,
 * a slave twice, no slave or too many.
 */
#define MC_ERR_GANTRY_AXES -127

/**
 * A gantry's yaw gains, skew limit or square offset out of range.
 */
#define MC_ERR_GANTRY_GAINS -128

/**
 * The gantry (or its axes) is not in a state that takes the command.
 */
#define MC_ERR_GANTRY_STATE -129

/**
 * Layout 1.11: a group home order that names an axis the group does not have (a group
 * axis index at or beyond its axis count).
 */
#define MC_ERR_HOME_AXIS -122

/**
 * A group home order that names an axis in two stages (or twice in one).
 */
#define MC_ERR_HOME_TWICE -123

/**
 * A group home order with an empty stage, or none at all when the group has no
 * configured order.
 */
#define MC_ERR_HOME_STAGE -124

/**
 * An arc whose plane of two group axes names one axis twice.
 */
#define MC_ERR_PLANE_AXES -130

/**
 * Layout 1.11: a servo filter's slot (0..4) or kind out of range.
 */
#define MC_ERR_FILTER_KIND -131

/**
 * A servo filter's frequency not above 0 and below the Nyquist frequency (half the servo
 * rate); also a servo rate at which a filter set would not be.
 */
#define MC_ERR_FILTER_FREQ -132

/**
 * A servo filter's damping (0 < damping <= 10), depth (-120..0 dB) or raw coefficient
 * out of range.
 */
#define MC_ERR_FILTER_PARAM -133

/**
 * The servo filter designed has a pole on or outside the unit circle (within the card's
 * margin of it): it would be unstable.
 */
#define MC_ERR_FILTER_UNSTABLE -134

/**
 * PID+FF gains refused: a gain negative, a derivative cut-off or friction deadband not
 * above 0.
 */
#define MC_ERR_PIDFF_GAINS -135

/**
 * Layout 1.11: an analog input or output the card does not have (inputs 0..=7, outputs
 * 0..=3), or a spare DAC output the path-speed output drives.
 */
#define MC_ERR_ANALOG_CHANNEL -136

/**
 * An analog input's cut-off below 0 or above half the servo rate (Nyquist).
 */
#define MC_ERR_ANALOG_FILTER -137

/**
 * An analog threshold beyond ±10 V, or a hysteresis below 0 or above 20 V.
 */
#define MC_ERR_ANALOG_THRESHOLD -138

/**
 * A path-speed output's output, gate, range (min > max, beyond ±10 V or a duty beyond
 * 0..1), reference speed (<= 0) or PWM frequency out of range, the gate on the PWM's own
 * output, or a PWM on an output a compare channel pulses.
 */
#define MC_ERR_PSO_CONFIG -139

/**
 * A path-speed output on a group that does not exist or is not configured.
 */
#define MC_ERR_PSO_GROUP -140

/**
 * `name:NAME` or `serial:N` matches more than one card listed (`mcctl list`, `mc_list_cards`):
 * open it by its URI instead (the message names them).
 */
#define MC_ERR_AMBIGUOUS -150

/**
 * Layout 1.12: a timed command for a tick the card has already run.
 */
#define MC_ERR_TICK_PASSED -152

/**
 * The card holds as many timed commands as it can (16).
 */
#define MC_ERR_TIMED_FULL -153

/**
 * A timing without its command, or of a command that cannot be timed (a session's, a
 * timing's or a commit's).
 */
#define MC_ERR_TIMED_ALONE -154

/**
 * A tick more than 600,000 ticks ahead, or a tick or key that is not a whole number in
 * range.
 */
#define MC_ERR_TICK_FAR -155

/**
 * The commit reached the bus's master on or after its tick: nothing of its key runs.
 */
#define MC_ERR_COMMIT_LATE -156

/**
 * A commit sent to a follower: commit on the bus's master.
 */
#define MC_ERR_NOT_MASTER -157

/**
 * A timed command whose commit the card had not seen by its tick: not run.
 */
#define MC_ERR_NOT_COMMITTED -158

/**
 * The card lost the sync bus's master: its timed commands are dropped, its motion halted.
 */
#define MC_ERR_SYNC_LOST -159

/**
 * The command of a refused timing: not run.
 */
#define MC_ERR_TIMED_REFUSED -160

/**
 * A held timed command dropped (a cancel, or the host's detach).
 */
#define MC_ERR_TIMED_CANCELLED -161

/**
 * Layout 1.12: a normal-vector arc's normal is zero, or no plane was set before it.
 */
#define MC_ERR_ARC_NORMAL -147

/**
 * A normal-vector arc's plane names a group axis twice.
 */
#define MC_ERR_ARC_AXES -148

/**
 * A normal-vector arc's centre, or its end (unless it rises along the normal), is off
 * the plane through the start by more than the group's tolerance.
 */
#define MC_ERR_ARC_OFF_PLANE -149

/**
 * Layout 1.13: a piece of a move-queue arc in a plane given by a normal vector alone or
 * out of order (its two command entries go together, the move first).
 */
#define MC_ERR_ARC_PIECE -151

/**
 * Layout 1.12: a frequency sweep's frequencies (0.1 Hz <= from <= to <= a quarter of the
 * servo rate), points (1..=256), cycles (1..=1000), settle time (0..=60 s) or mode out of
 * range.
 */
#define MC_ERR_FREQ_RANGE -141

/**
 * A frequency sweep's amplitude not above 0, or (on the servo output) above the axis's
 * DAC limit.
 */
#define MC_ERR_FREQ_AMPLITUDE -142

/**
 * The sweep's sine would break the axis's limits: its velocity (amplitude 2 pi f above the
 * safety's max velocity), acceleration, following error at rest (2 amplitude above
 * min_ferror) or soft limits.
 */
#define MC_ERR_FREQ_LIMITS -143

/**
 * A sweep is running: another sweep, or that axis's own motion, refused.
 */
#define MC_ERR_FREQ_BUSY -144

/**
 * Layout 1.12: a compare channel armed on the digital output the path-speed output's PWM
 * holds.
 */
#define MC_ERR_PSO_OUTPUT -145

/**
 * Layout 1.13: compare on a modulo (rotary) axis: a position off the turn (not in
 * `[0, modulo)`), a series longer than a turn, each turn on a linear axis, or the period
 * changed while a compare channel watches the axis.
 */
#define MC_ERR_COMPARE_TURN -146

/**
 * Layout 1.14, paths across cards: path dimensions that do not name each group axis once
 * (or more than 16), or a staging command on a group without dimensions.
 */
#define MC_ERR_PATH_DIMS -162

/**
 * A segment across cards whose two command entries did not come together.
 */
#define MC_ERR_PATH_MORE -163

/**
 * A release of more segments than are staged, or of segments staged from where the
 * group no longer is.
 */
#define MC_ERR_PATH_RELEASE -164

/**
 * The card handle (or motion) is unknown: never opened, or already closed.
 */
#define MC_ERR_BAD_HANDLE -100

/**
 * A pointer argument that must not be NULL was NULL.
 */
#define MC_ERR_NULL_POINTER -101

/**
 * The buffer is too small; the size needed (with the terminating NUL) was written to `*needed`.
 */
#define MC_ERR_BUFFER_TOO_SMALL -102

/**
 * The library panicked (a bug in libmotioncard); the call had no effect on the caller's
 * outputs. The message is in `mc_last_error_message`.
 */
#define MC_ERR_PANIC -103







/**
 * Set analog input `input`'s (0..7) filter and threshold. The filter keeps its value; the
 * threshold state is taken again from it, without an event. Refused: `MC_ERR_ANALOG_CHANNEL`,
 * `MC_ERR_ANALOG_FILTER` (a cut-off below 0 or above half the servo rate),
 * `MC_ERR_ANALOG_THRESHOLD`, `MC_ERR_NOT_FINITE`; nothing changes then. Blocks until the card
 * answers.
 */
mc_result mc_analog_input_configure(mc_card card,
                                    uint32_t input,
                                    const struct mc_analog_input_settings *settings);

/**
 * Analog input `input` (0..7) as the card sampled it at its last tick. Never blocks.
 */
mc_result mc_analog_input_read(mc_card card, uint32_t input, struct mc_analog_input_info *info);

/**
 * Set spare DAC output `output` (0..3) to `volts`, clamped to the 12-bit DAC's range (-10 V ..
 * 10 V - 20/4096 V) and quantised; `*produced` (may be NULL) receives the volts it puts out.
 * Refused: `MC_ERR_ANALOG_CHANNEL` (no such output, or the one the PSO drives),
 * `MC_ERR_NOT_FINITE`. Blocks until the card answers.
 */
mc_result mc_analog_output_set(mc_card card, uint32_t output, double volts, double *produced);

/**
 * Spare DAC output `output` (0..3) now, V. Never blocks.
 */
mc_result mc_analog_output_get(mc_card card, uint32_t output, double *volts);

/**
 * Run the path-speed output on `group`: every tick, while the gate output is on, the output is
 * `clamp(min + (max - min) * v / v_ref, min, max)`, v the group's actual tangential speed
 * (its axes' velocity estimates through the speed filter); 0 (0 V, or duty 0) while the gate
 * is off. Replaces a PSO running. Refused: `MC_ERR_PSO_GROUP` (no such group, or not
 * configured), `MC_ERR_PSO_CONFIG` (min > max, a range, output, gate, v_ref, frequency or
 * filter out of range), `MC_ERR_NOT_FINITE`; nothing changes then. Blocks until the card
 * answers.
 */
mc_result mc_pso_configure(mc_card card, uint32_t group, const struct mc_pso_settings *settings);

/**
 * Stop the path-speed output: its output goes to 0. Blocks until the card answers.
 */
mc_result mc_pso_off(mc_card card);

/**
 * The path-speed output's state, speed and value of the last tick. Never blocks.
 */
mc_result mc_pso_get_info(mc_card card, struct mc_pso_info *info);

/**
 * Stepped sim: drive analog input `input`'s pin at `volts` now. `MC_ERR_UNSUPPORTED` on any
 * other card. Never blocks.
 */
mc_result mc_sim_set_analog_input(mc_card card, uint32_t input, double volts);

/**
 * A static description of a result code ("unknown result code" for a value that is not one).
 * Never NULL; the string lives as long as the program. Never blocks, never fails.
 */
const char *mc_result_str(mc_result code);

/**
 * The detailed message of the last failed `mc_` call on the calling thread ("" when none
 * failed). Successful calls leave it as it was. Copies the message and a NUL into `buf` and
 * the size it takes (including the NUL) into `*needed`. When `len` is too small, writes only
 * `*needed` and returns `MC_ERR_BUFFER_TOO_SMALL`; `buf` may be NULL when `len` is 0 (to ask
 * for the size). This call's own failures do not replace the message.
 */
mc_result mc_last_error_message(char *buf, size_t len, size_t *needed);

/**
 * The library's version, `major << 16 | minor << 8 | patch` (as `mc_card_info.firmware_version`).
 */
mc_result mc_version(uint32_t *version);

/**
 * The library's version as a string ("0.1.0"), with the buffer rules of
 * `mc_last_error_message`.
 */
mc_result mc_version_string(char *buf, size_t len, size_t *needed);

/**
 * Open a card by URI: `sim` (an emulated card in this process, real-time clock), `emu:NAME`
 * (a `card-emu` process), `uio:/dev/uioN` or `pci:DDDD:BB:DD.F` (hardware). Writes its handle
 * to `*card`. Blocks until the card has answered (at most about a second).
 */
mc_result mc_open(const char *uri, mc_card *card);

/**
 * Open an emulated card in this process whose time advances only in `mc_sim_step` and in
 * waits (a wait's timeout is then in emulated time): deterministic, for tests. `axes` is
 * 1..8 and `servo_rate_hz` 1000..20000; anything outside is `MC_ERR_BAD_CONFIG` (as
 * `mc_open_sim`, of which this is the stepped, default-plant case).
 */
mc_result mc_open_sim_stepped(int axes, uint32_t servo_rate_hz, mc_card *card);

/**
 * The options of `mc_open("sim")`: real-time clock, 8 axes, 10 kHz, the default plant.
 * Never blocks.
 */
mc_result mc_sim_options_default(struct mc_sim_options *options);

/**
 * Open an emulated card in this process with explicit options: its clock
 * (`MC_SIM_CLOCK_REAL_TIME`, `_FREE_RUNNING`, or `_STEPPED` for a card whose time advances only
 * in `mc_sim_step` and waits), axes (1..8), servo rate (1000..20000 Hz) and plant
 * (`MC_SIM_PLANT_`). Values out of range, or unknown clocks and plants, are
 * `MC_ERR_BAD_CONFIG`. Blocks until the card has booted.
 */
mc_result mc_open_sim(const struct mc_sim_options *options, mc_card *card);

/**
 * Close a card: the clean end of this program's session. Moving axes and groups halt along
 * their stop ramps (stop reason `MC_STOP_REASON_HOST_DETACH`), the card's watchdog is
 * disarmed without latching a fault (the next program opens a card that is ready to move),
 * and the heartbeat stops. Every call blocked on this card in another thread
 * (`mc_motion_wait`, `mc_wait_done`, `mc_wait_event`, `mc_group_wait_done`,
 * `mc_dispatch_events`...) returns `MC_ERR_CLOSED` at once. The handle is invalid afterwards:
 * closing it again, or any other call with it, returns `MC_ERR_BAD_HANDLE` and does nothing
 * else (double close is harmless). The handle is closed even when the card could not be told
 * (a card that does not answer: the code says why, and its watchdog then stops it). Blocks
 * until the card has answered the close.
 */
mc_result mc_close(mc_card card);

/**
 * End every wait in progress on this card in other threads (`mc_motion_wait`, `mc_wait_done`,
 * `mc_wait_event`, `mc_group_wait_done`, `mc_group_motion_wait`, `mc_dispatch_events`): each
 * returns `MC_ERR_CANCELLED`. Waits that begin afterwards are not affected; a call waiting for
 * the card's answer to its own command is not cancelled (the command may still run). Never
 * blocks.
 */
mc_result mc_cancel_waits(mc_card card);

/**
 * How many axes this program's `mc_open` stopped because the program before it left the card
 * without closing it (it crashed or was killed): those axes are in ErrorStop with stop reason
 * `MC_STOP_REASON_HOST_CHANGED` until `mc_reset_faults`. 0 when the previous program closed
 * the card or left nothing enabled. Never blocks.
 */
mc_result mc_inherited_stops(mc_card card, uint32_t *axes);

/**
 * What the card says about itself: firmware and layout versions, axes, servo rate.
 */
mc_result mc_get_info(mc_card card, struct mc_card_info *info);

/**
 * The card's servo tick counter.
 */
mc_result mc_get_tick(mc_card card, uint64_t *tick);

/**
 * A command that does nothing but come back: one round trip through the card. Blocks until
 * the card answers.
 */
mc_result mc_ping(mc_card card);

/**
 * Change the servo rate (1000..20000 Hz; every axis must be disabled). Blocks until the card
 * answers.
 */
mc_result mc_set_servo_rate(mc_card card, uint32_t servo_rate_hz);

/**
 * Events lost: `*dropped` were dropped from the library's queue because nobody took them
 * (beyond 4096 waiting), `*card_lost` could not be posted by the card (its ring was full).
 */
mc_result mc_events_lost(mc_card card, uint64_t *dropped, uint32_t *card_lost);

/**
 * The default servo gains and in-position windows.
 */
mc_result mc_axis_settings_default(mc_axis_settings *settings);

/**
 * Write an axis's servo and in-position configuration and have the card apply it (the card
 * checks every value: `MC_ERR_BAD_CONFIG`). Blocks until the card answers.
 */
mc_result mc_configure(mc_card card, uint32_t axis, const mc_axis_settings *settings);

/**
 * Counts per user unit for this axis (default 1: positions in counts). Positions, velocities,
 * limits and status fields other than `raw` are then in user units. A negative scale reverses
 * the axis; zero, and |scale| outside 1e-9..1e12, is `MC_ERR_BAD_CONFIG`. Layout 1.8: the card
 * keeps the scale for hosts (`mc_axis_settings.scale`, read back with `mc_axis_get_settings`),
 * and a process that opens the card later adopts it. Blocks until the card answers.
 */
mc_result mc_set_scale(mc_card card, uint32_t axis, double counts_per_unit);

/**
 * MC_Power on. Blocks until the card answers.
 */
mc_result mc_enable(mc_card card, uint32_t axis);

/**
 * MC_Power off (a moving axis loses power at once; its motion is aborted). Blocks until the
 * card answers.
 */
mc_result mc_disable(mc_card card, uint32_t axis);

/**
 * Symmetric move limits: deceleration = acceleration, one jerk for all four phases. Fills
 * `*limits`; nothing is checked until a move uses them.
 */
mc_result mc_move_limits_symmetric(double velocity,
                                   double acceleration,
                                   double jerk,
                                   struct mc_move_limits *limits);

/**
 * MC_MoveAbsolute (PLCopen Aborting): a time-optimal S-curve to `target` within `*limits`,
 * from Standstill or from whatever the axis is doing (it takes over in the tick the card
 * serves it; the motion it replaces is aborted). `MC_ERR_AXIS_DISABLED` when disabled,
 * `MC_ERR_INVALID_STATE` while stopping or in ErrorStop. Buffered moves: `mc_move`. `motion`
 * may be NULL; otherwise it receives the motion to wait for. Blocks until the card has
 * accepted or refused the move, not until it is done.
 */
mc_result mc_move_absolute(mc_card card,
                           uint32_t axis,
                           double target,
                           const struct mc_move_limits *limits,
                           struct mc_motion *motion);

/**
 * MC_MoveRelative: a time-optimal S-curve by `distance`; otherwise as `mc_move_absolute`.
 */
mc_result mc_move_relative(mc_card card,
                           uint32_t axis,
                           double distance,
                           const struct mc_move_limits *limits,
                           struct mc_motion *motion);

/**
 * MC_Halt: decelerate (at most `deceleration`, with `jerk`), then Standstill. The
 * interrupted move is aborted. `motion` (may be NULL) receives the halt, which is done when
 * the axis is at rest in position. Blocks until the card answers.
 */
mc_result mc_halt(mc_card card,
                  uint32_t axis,
                  double deceleration,
                  double jerk,
                  struct mc_motion *motion);

/**
 * MC_Stop: decelerate and stay in Stopping (moves refused) until `mc_release_stop`.
 * Otherwise as `mc_halt`.
 */
mc_result mc_stop(mc_card card,
                  uint32_t axis,
                  double deceleration,
                  double jerk,
                  struct mc_motion *motion);

/**
 * Leave Stopping (once at rest the axis goes to Standstill). Blocks until the card answers.
 */
mc_result mc_release_stop(mc_card card, uint32_t axis);

/**
 * MC_Reset: ErrorStop → Standstill (`MC_ERR_INVALID_STATE` in any other state). Blocks until
 * the card answers.
 */
mc_result mc_reset(mc_card card, uint32_t axis);

/**
 * A consistent snapshot of an axis's status, read from the block the card publishes every
 * servo tick (and before each event it posts). Does not wait for the card; see the header's
 * notes on blocking.
 */
mc_result mc_get_status(mc_card card, uint32_t axis, struct mc_status *status);

/**
 * The status of several axes in one call: `statuses[i]` is the status of axis `axes[i]`, for
 * `n` axes (1..=8; each a valid axis, repeats allowed), all of the same servo tick (equal
 * `raw.tick`: a read that straddles two ticks is read again), each a consistent snapshot,
 * and one check that the card is alive. Like
 * `mc_get_status`, never stale: `MC_ERR_NOT_RESPONDING` when the card's tick has stood still
 * too long. Does not wait for the card.
 */
mc_result mc_get_statuses(mc_card card, const uint32_t *axes, size_t n, struct mc_status *statuses);

/**
 * Wait until a motion is done (in position). `position` may be NULL; otherwise it receives
 * the actual position when the motion was done. `MC_ERR_ABORTED` when another command or a
 * fault ended it, `MC_ERR_TIMEOUT` after `timeout_ms` (0: only look). A motion can be waited
 * for more than once. `MC_ERR_BAD_HANDLE` for a motion that was not started on this card (the
 * last 1024 motions are kept). Blocks.
 */
mc_result mc_motion_wait(mc_card card,
                         struct mc_motion motion,
                         uint32_t timeout_ms,
                         double *position);

/**
 * Wait for the last motion started on this axis by this process, as `mc_motion_wait`
 * (`position` may be NULL). `MC_ERR_NO_MOTION` when none was started since the card was opened
 * (nothing to wait for). Blocks.
 */
mc_result mc_wait_done(mc_card card, uint32_t axis, uint32_t timeout_ms, double *position);

/**
 * Take the next event from the card, waiting up to `timeout_ms` (0: don't wait);
 * `MC_ERR_TIMEOUT` when none came. Each event is delivered once, to whichever of
 * `mc_wait_event` and `mc_dispatch_events` takes it first. Blocks.
 */
mc_result mc_wait_event(mc_card card, uint32_t timeout_ms, struct mc_event *event);

/**
 * The card's interrupt file descriptor, for the application's own poll/epoll loop: it becomes
 * readable when the card raises an interrupt; then call `mc_dispatch_events` (or
 * `mc_poll_events`). The descriptor belongs to the library: do not read, write or close it;
 * it stays valid until `mc_close`. `MC_ERR_UNSUPPORTED` for `pci:` cards (no interrupt line).
 */
mc_result mc_irq_fd(mc_card card, int *fd);

/**
 * Take what the card posted into the library's event queue without waiting (clears the
 * interrupt descriptor's readiness); `*queued` is how many events were added. Never blocks.
 */
mc_result mc_poll_events(mc_card card, size_t *queued);

/**
 * Set the card's event callback (NULL: none). `user` is handed back to it untouched. The
 * callback is called only from `mc_dispatch_events`, on the thread that calls it: the library
 * starts no thread that calls into the application. It may call any `mc_` function, including
 * `mc_close` on this card.
 */
mc_result mc_set_event_callback(mc_card card, mc_event_callback callback, void *user);

/**
 * Take the card's events and call the callback once for each, in order, on this thread.
 * Waits up to `timeout_ms` for the first one (0: don't wait; call it when the descriptor of
 * `mc_irq_fd` is readable), then takes the rest without waiting (at most 4096 per call); the
 * callback then gets every event taken, even if it closes the card. A close from another
 * thread ends the wait: `MC_ERR_CLOSED`.
 * Without a callback the events are taken and dropped. `*dispatched` is how many were taken;
 * 0 with `MC_OK` when none came. Blocks up to `timeout_ms`.
 */
mc_result mc_dispatch_events(mc_card card, uint32_t timeout_ms, size_t *dispatched);

/**
 * Advance a stepped sim card (`mc_open_sim_stepped`) by `ticks` servo periods.
 * `MC_ERR_UNSUPPORTED` on any other card. Blocks for the computation.
 */
mc_result mc_sim_step(mc_card card, uint64_t ticks);

/**
 * Emulated time of a stepped sim card since boot, in seconds.
 */
mc_result mc_sim_time(mc_card card, double *seconds);

/**
 * Load cam table `table` with `n` points (`master[i]`, `slave[i]`, counts; the master strictly
 * increasing; 2 ..= `MC_CAM_MAX_POINTS`, cubic 3 ..), `flags` `MC_CAM_CUBIC`,
 * `MC_CAM_PERIODIC`. `MC_ERR_CAM_TABLE` if the card refuses it (or a slave follows it),
 * `MC_ERR_NOT_FINITE`. Blocks until the card answers.
 */
mc_result mc_cam_load_table(mc_card card,
                            uint32_t table,
                            const double *master,
                            const double *slave,
                            size_t n,
                            uint32_t flags);

/**
 * MC_CamIn (Aborting): `axis` follows master `master` of kind `master_kind` (`MC_MASTER_`)
 * through `cam`, caught up within `limits`; `mc_motion_wait_in_sync` on `*motion` (may be
 * NULL) returns once it is on the cam. `MC_ERR_CAM_TABLE` for a table not loaded. Blocks until
 * the card answers.
 */
mc_result mc_cam_in(mc_card card,
                    uint32_t axis,
                    uint32_t master_kind,
                    uint32_t master,
                    const struct mc_cam_settings *cam,
                    const struct mc_sync_limits *limits,
                    struct mc_motion *motion);

/**
 * On an axis that cams: `cam`'s table takes over at the end of the current cycle, the slave's
 * position continuous (`mc_motion_wait_cam_switch` on `*motion`, may be NULL).
 * `MC_ERR_INVALID_STATE` if the axis does not cam. Blocks until the card answers.
 */
mc_result mc_cam_switch(mc_card card,
                        uint32_t axis,
                        uint32_t master_kind,
                        uint32_t master,
                        const struct mc_cam_settings *cam,
                        const struct mc_sync_limits *limits,
                        struct mc_motion *motion);

/**
 * MC_CamOut: the slave leaves the cam in velocity mode at its velocity
 * (`mc_motion_wait_in_velocity` on `*motion`, may be NULL). Blocks until the card answers.
 */
mc_result mc_cam_out(mc_card card, uint32_t axis, struct mc_motion *motion);

/**
 * Wait until the table switch of `mc_cam_switch` took place. `position` may be NULL;
 * otherwise it receives the slave's commanded position then. Blocks.
 */
mc_result mc_motion_wait_cam_switch(mc_card card,
                                    struct mc_motion motion,
                                    uint32_t timeout_ms,
                                    double *position);

/**
 * Load `axis`'s compensation: `settings` and `n` points (at most 256; 0: only the backlash, or
 * compensation off). Checked whole first: `MC_ERR_COMP_TABLE` (count, bound, backlash, ramp),
 * `MC_ERR_COMP_ORDER` (positions not strictly increasing), `MC_ERR_COMP_BOUND`,
 * `MC_ERR_NOT_FINITE`; `MC_ERR_COMP_BUSY` if the axis is not at rest. A refusal changes
 * nothing. Blocks until the card answers.
 */
mc_result mc_axis_set_compensation(mc_card card,
                                   uint32_t axis,
                                   const struct mc_comp_settings *settings,
                                   const struct mc_comp_table_point *points,
                                   size_t n);

/**
 * Switch `axis`'s compensation off (its correction ramps out). `MC_ERR_COMP_BUSY` if the axis
 * is not at rest.
 */
mc_result mc_axis_clear_compensation(mc_card card, uint32_t axis);

/**
 * Read `axis`'s compensation back from the card: its settings into `*settings` and its points
 * into `points` (room for `len`), their count into `*needed` (0 and zero settings: no
 * compensation). `MC_ERR_BUFFER_TOO_SMALL` (only `*needed` written) if `len` is short.
 */
mc_result mc_axis_get_compensation(mc_card card,
                                   uint32_t axis,
                                   struct mc_comp_settings *settings,
                                   struct mc_comp_table_point *points,
                                   size_t len,
                                   size_t *needed);

/**
 * Run a sweep on an enabled axis at rest and wait for its end (up to `timeout_ms` of the
 * card's time): its points into `points` (`len` of them; `*needed` the count; too small:
 * `MC_ERR_BUFFER_TOO_SMALL`, the sweep's result stays on the card for
 * `mc_axis_freq_result`). Refused, nothing changed: `MC_ERR_FREQ_RANGE`,
 * `MC_ERR_FREQ_AMPLITUDE`, `MC_ERR_FREQ_LIMITS`, `MC_ERR_FREQ_BUSY`, `MC_ERR_NOT_FINITE`,
 * `MC_ERR_AXIS_DISABLED`, `MC_ERR_INVALID_STATE`; ended early (a stop, a safety stop):
 * `MC_ERR_ABORTED`.
 */
mc_result mc_axis_freq_response(mc_card card,
                                uint32_t axis,
                                const struct mc_freq_sweep *sweep,
                                uint32_t timeout_ms,
                                struct mc_freq_point *points,
                                size_t len,
                                size_t *needed);

/**
 * The last sweep's points of this axis as the card holds them (the same as
 * `mc_axis_freq_response` gave), and `*complete` 1 when every point was measured. Never
 * blocks.
 */
mc_result mc_axis_freq_result(mc_card card,
                              uint32_t axis,
                              struct mc_freq_point *points,
                              size_t len,
                              size_t *needed,
                              uint32_t *complete);

/**
 * The resonances (peaks) and anti-resonances (dips) of the axis's last sweep's response
 * standing out by at least 3 dB (the plant's with its rigid-body slope taken out). Never
 * blocks.
 */
mc_result mc_axis_freq_resonances(mc_card card,
                                  uint32_t axis,
                                  struct mc_freq_resonance *found,
                                  size_t len,
                                  size_t *needed);

/**
 * Stop the card's sweep (none running: nothing happens). Blocks until the card answers.
 */
mc_result mc_axis_freq_stop(mc_card card, uint32_t axis);

/**
 * Form gantry `index` (0..3) of `master` and `nslaves` slaves (1..4, each with the master's
 * scale), `offsets` the slaves' square offsets (NULL: all 0). Every member at rest, all
 * powered or all disabled; nothing moves. Refused: `MC_ERR_GANTRY_AXES` (the master among the
 * slaves, a slave twice, a count), `MC_ERR_BAD_AXIS`, `MC_ERR_GANTRY_GAINS`,
 * `MC_ERR_NOT_FINITE`, `MC_ERR_GANTRY_IN_USE` (a member in another gantry, geared, streaming;
 * a slave in a group), `MC_ERR_GANTRY_STATE`, `MC_ERR_BAD_CONFIG` (different scales).
 */
mc_result mc_gantry_form(mc_card card,
                         uint32_t index,
                         uint32_t master,
                         const uint32_t *slaves,
                         size_t nslaves,
                         const struct mc_gantry_settings *settings,
                         const double *offsets);

/**
 * Home gantry `index` and wait up to `timeout_ms`: each side runs its own homing method, then
 * the slaves square the bridge to their offsets. `*skew` (may be NULL): slave 0's skew once
 * squared. `MC_ERR_HOMING_FAILED` when a side failed (the message names the gantry and the
 * axis; the gantry is coupled where it stopped), `MC_ERR_GANTRY_STATE` when a member is not at
 * rest, `MC_ERR_TIMEOUT`.
 */
mc_result mc_gantry_home(mc_card card, uint32_t index, uint32_t timeout_ms, double *skew);

/**
 * Gantry `index`'s status. `MC_ERR_GANTRY_STATE` when it is not formed.
 */
mc_result mc_gantry_get_info(mc_card card, uint32_t index, struct mc_gantry_info *info);

/**
 * Dissolve gantry `index`: the master at rest (`MC_ERR_GANTRY_STATE`); the slaves hold where
 * they are, each its own axis again.
 */
mc_result mc_gantry_dissolve(mc_card card, uint32_t index);

/**
 * The defaults: axes "XYZ", rapids and feeds up to 100 mm/s, 0.01 mm corners and splines,
 * block delete and optional stop off, no probe input, no spindle or coolant outputs on
 * the card (-1), the run measured (`report` 1).
 */
mc_result mc_gcode_default_settings(struct mc_gcode_settings *settings);

/**
 * Load the program file `path` for `group` of `card` (enabled, its path configured with
 * `mc_group_configure_path`): it is read whole once and checked (`MC_ERR_GCODE` for the
 * first wrong line, `mc_last_error_message` giving `line N: what`; nothing is queued), then
 * `*program` is its handle. It starts where the group is. `tool_table` (may be NULL) is a
 * tool table file in LinuxCNC's format; `settings` may be NULL for the defaults. A call of
 * a subroutine the program does not define (`o<name> call`) runs `name.ngc` from the
 * program's directory.
 */
mc_result mc_gcode_load_file(mc_card card,
                             uint32_t group,
                             const char *path,
                             const char *tool_table,
                             const struct mc_gcode_settings *settings,
                             mc_gcode *program);

/**
 * `mc_gcode_load_file` for a program in memory: `text`, NUL-terminated (copied).
 */
mc_result mc_gcode_load_string(mc_card card,
                               uint32_t group,
                               const char *text,
                               const char *tool_table,
                               const struct mc_gcode_settings *settings,
                               mc_gcode *program);

/**
 * Set the program's hooks (`hooks` copied; NULL clears them) and the `user` pointer they
 * get back.
 */
mc_result mc_gcode_set_hooks(mc_gcode program, const struct mc_gcode_hooks *hooks, void *user);

/**
 * One step of the run, never blocking: program lines read and queued while the path has
 * room, a waiting operation done once the motion before it has ended (its hook called).
 * `*state` (may be NULL): `MC_GCODE_*`. An error (`MC_ERR_GCODE` for a wrong line, or the
 * card's or a hook's code) aborts the run; what was queued before it runs to its end.
 */
mc_result mc_gcode_poll(mc_gcode program, uint32_t *state);

/**
 * Poll until the program is done, paused or aborted, at most `timeout_ms` (`MC_ERR_TIMEOUT`
 * after it, the run going on). A stepped in-process card is stepped here. Another thread
 * may call `mc_gcode_pause`, `mc_gcode_abort` or `mc_gcode_line` meanwhile.
 */
mc_result mc_gcode_run(mc_gcode program, uint32_t timeout_ms, uint32_t *state);

/**
 * Pause at the end of a block: the card brings the path to rest at the end of the first block
 * it can stop at within its limits from where it is (the running block where it can; an exact
 * stop or a dwell's end always can), and `mc_gcode_run` then returns `MC_GCODE_PAUSED`. A block
 * followed by a blend pauses where the blend starts, within its tolerance of the block's end.
 * What is queued stays queued; `mc_gcode_resume` goes on along the same path.
 */
mc_result mc_gcode_pause(mc_gcode program);

/**
 * Go on after a pause (M0/M1/M60 or `mc_gcode_pause`).
 */
mc_result mc_gcode_resume(mc_gcode program);

/**
 * Abort: the path halts along its geometry within `deceleration` (mm/s²) and `jerk`
 * (mm/s³), nothing more is read; the state is `MC_GCODE_ABORTED`.
 */
mc_result mc_gcode_abort(mc_gcode program, double deceleration, double jerk);

/**
 * `*running` (may be NULL): the source line of the segment the card runs (0 when none);
 * `*read` (may be NULL): the last source line read.
 */
mc_result mc_gcode_line(mc_gcode program, uint32_t *running, uint32_t *read);

/**
 * What the run did so far (`mc_path_report`): during the run, or after it (done, paused or
 * aborted). `MC_ERR_UNSUPPORTED` when the program was loaded with `settings.report` 0, or
 * when the card moved before the program had a motion to measure it against.
 */
mc_result mc_gcode_report(mc_gcode program, struct mc_path_report *report);

/**
 * The error that stopped the run: `*line` its source line (0: no error, or none to name)
 * and its message into `buf` (the string conventions; "" when none).
 */
mc_result mc_gcode_error(mc_gcode program, uint32_t *line, char *buf, size_t len, size_t *needed);

/**
 * Close the program: its handle is no longer valid. Motion already queued on the card runs
 * on (`mc_gcode_abort` first to stop it).
 */
mc_result mc_gcode_close(mc_gcode program);

/**
 * Settings for a group of the `naxes` card axes in `axes` (group axis 0 is X, 1 is Y, …):
 * S-curve feed (`MC_GROUP_ACCDEC_PRE`), exact arcs, tolerance 2 (user units of the first axis:
 * adjust it after `mc_set_scale`). `naxes` is 1..8 (`MC_ERR_BAD_AXIS`); the axis numbers are
 * checked by `mc_group_configure`. Never blocks.
 */
mc_result mc_group_settings_new(const uint32_t *axes,
                                size_t naxes,
                                struct mc_group_settings *settings);

/**
 * Configure a group: its axes, acc/dec mode, arc interpolator, tolerance and home order. The
 * group must be disabled; the card checks every value (`MC_ERR_BAD_AXIS`,
 * `MC_ERR_AXIS_IN_OTHER_GROUP`, `MC_ERR_INCOMPATIBLE_MODE`, …). Unknown `MC_GROUP_ACCDEC_` /
 * `MC_GROUP_INTERP_` values and `home_stages` above 8 are `MC_ERR_BAD_CONFIG`; a bad home
 * order is refused as `mc_group_home` refuses one (`MC_ERR_HOME_AXIS`, `MC_ERR_HOME_TWICE`,
 * `MC_ERR_HOME_STAGE`), the card's configuration unchanged. Blocks until the card answers.
 */
mc_result mc_group_configure(mc_card card,
                             uint32_t group,
                             const struct mc_group_settings *settings);

/**
 * MC_GroupEnable: GroupDisabled → GroupStandby. Every axis of the group must be enabled and at
 * rest. Blocks until the card answers.
 */
mc_result mc_group_enable(mc_card card, uint32_t group);

/**
 * MC_GroupDisable: aborts the queued moves and leaves the axes enabled where they are. Blocks
 * until the card answers.
 */
mc_result mc_group_disable(mc_card card, uint32_t group);

/**
 * MC_GroupReset: GroupErrorStop → GroupStandby (`MC_ERR_INVALID_STATE` in any other state).
 * Blocks until the card answers.
 */
mc_result mc_group_reset(mc_card card, uint32_t group);

/**
 * MC_GroupHalt: decelerate along the path (at most `deceleration`, with `jerk`, user units
 * of the first axis), then GroupStandby; the queued moves are aborted. `motion` (may be NULL)
 * receives the halt, done when the group is at rest. Blocks until the card answers.
 */
mc_result mc_group_halt(mc_card card,
                        uint32_t group,
                        double deceleration,
                        double jerk,
                        struct mc_group_motion *motion);

/**
 * MC_GroupStop: decelerate along the path and stay in GroupStopping (moves refused) until
 * `mc_group_release_stop`. Otherwise as `mc_group_halt`.
 */
mc_result mc_group_stop(mc_card card,
                        uint32_t group,
                        double deceleration,
                        double jerk,
                        struct mc_group_motion *motion);

/**
 * Leave GroupStopping (once at rest the group goes to GroupStandby). Blocks until the card
 * answers.
 */
mc_result mc_group_release_stop(mc_card card, uint32_t group);

/**
 * MC_SetOverride of a group: `feed` scales the path speed of lines and arcs, `rapid` that of
 * point-to-point moves, each 0.0 to 2.0 (0 % to 200 %; else `MC_ERR_OVERRIDE_RANGE`). The
 * active move is replanned along its path within the path limits; 0 holds the group on its
 * path, a factor above 0 resumes. Blocks until the card answers.
 */
mc_result mc_group_set_override(mc_card card, uint32_t group, double feed, double rapid);

/**
 * MC_MoveLinearAbsolute / Relative: a straight line to `target` (`n` values, one per group
 * axis in group order, user units; `MC_ERR_BAD_AXIS` when `n` is not the group's axis count)
 * at the tangential feed of `*limits`. `options->buffered` queues it behind the moves already
 * queued (up to 32); otherwise the group must be at rest. `motion` may be NULL; otherwise it
 * receives the move to wait for. Blocks until the card has accepted or refused the move, not
 * until it is done.
 */
mc_result mc_group_move_linear(mc_card card,
                               uint32_t group,
                               const double *target,
                               size_t n,
                               const struct mc_path_limits *limits,
                               const struct mc_move_options *options,
                               struct mc_group_motion *motion);

/**
 * Synchronised point-to-point move (Kim eq 10–14): every axis starts and ends together, each
 * within `*limits` (the first axis's units): the axis with the longest distance moves at them
 * and the others scale. The cutting feed type becomes rapid. Otherwise as
 * `mc_group_move_linear`. `mc_group_move_ptp_axes` gives each axis its own limits.
 */
mc_result mc_group_move_ptp(mc_card card,
                            uint32_t group,
                            const double *target,
                            size_t n,
                            const struct mc_path_limits *limits,
                            const struct mc_move_options *options,
                            struct mc_group_motion *motion);

/**
 * Synchronised point-to-point move with each axis's own limits (Kim eq 10–14): `axis_limits`
 * holds `nlimits` `mc_path_limits`, one per group axis in group order, each in that axis's
 * user units (`MC_ERR_BAD_AXIS` when `n` or `nlimits` is not the group's axis count). The axis
 * that needs the most time within its limits sets the time, the others scale, every axis
 * stays within its own limits, and all start and end on the same servo tick. Otherwise as
 * `mc_group_move_ptp`; blocks until the card has accepted or refused the limits and the move.
 */
mc_result mc_group_move_ptp_axes(mc_card card,
                                 uint32_t group,
                                 const double *target,
                                 size_t n,
                                 const struct mc_path_limits *axis_limits,
                                 size_t nlimits,
                                 const struct mc_move_options *options,
                                 struct mc_group_motion *motion);

/**
 * MC_MoveCircular: an arc in `plane` (`MC_ARC_PLANE_`), described by `*arc` in the plane's
 * coordinates. `helix` holds `nhelix` targets of the group's other axes (in group order),
 * which move linearly with the arc (a helix); `nhelix` 0 (helix may then be NULL) keeps them
 * where they are. The card checks the geometry: `MC_ERR_ZERO_LENGTH_ARC`,
 * `MC_ERR_CENTRE_NOT_EQUIDISTANT`, `MC_ERR_RADIUS_TOO_SMALL`, `MC_ERR_COLLINEAR_POINTS`.
 * Otherwise as `mc_group_move_linear`.
 */
mc_result mc_group_move_circular(mc_card card,
                                 uint32_t group,
                                 const struct mc_arc *arc,
                                 uint32_t plane,
                                 const double *helix,
                                 size_t nhelix,
                                 const struct mc_path_limits *limits,
                                 const struct mc_move_options *options,
                                 struct mc_group_motion *motion);

/**
 * Layout 1.13: MC_MoveCircular in a plane given by a normal vector (`*arc`, see
 * `mc_normal_arc`): a rest-to-rest S-curve along the arc within `*limits` (along the path, as
 * `mc_group_move_circular`). `helix` holds `nhelix` targets of the group's other axes (in
 * group order; `nhelix` 0 keeps them where they are, `helix` may then be NULL). The three
 * axes need one scale. The card checks the geometry: `MC_ERR_ARC_NORMAL` (a zero normal),
 * `MC_ERR_ARC_AXES` (an axis twice), `MC_ERR_ARC_OFF_PLANE` (the centre, or the end without
 * `rise`, off the plane), `MC_ERR_CENTRE_NOT_EQUIDISTANT` (the end off the circle),
 * `MC_ERR_ZERO_LENGTH_ARC`. The move takes two command entries, sent together
 * (`MC_ERR_ARC_PIECE` if the card saw one alone). Otherwise as `mc_group_move_linear`.
 */
mc_result mc_group_move_circular_normal(mc_card card,
                                        uint32_t group,
                                        const struct mc_normal_arc *arc,
                                        const double *helix,
                                        size_t nhelix,
                                        const struct mc_path_limits *limits,
                                        const struct mc_move_options *options,
                                        struct mc_group_motion *motion);

/**
 * Path limits with the deceleration equal to the acceleration (`PathLimits::new`): feed
 * `velocity`, `acceleration`, `jerk`, in user units of the group's first axis. Nothing is
 * checked until a move uses them. Never blocks.
 */
mc_result mc_path_limits_new(double velocity,
                             double acceleration,
                             double jerk,
                             struct mc_path_limits *limits);

/**
 * A NURBS feed with the SDK's defaults (`NurbsFeed::new`): `feed`, `accel`, `jerk` as given,
 * the default chord tolerance (`chord_tolerance` 0: one encoder count), not saturation-aware.
 * Nothing is checked until a move uses it. Never blocks.
 */
mc_result mc_nurbs_feed_new(double feed, double accel, double jerk, struct mc_nurbs_feed *out);

/**
 * Move along a NURBS curve of `degree` (1..5) in `dim` dimensions (the group's axis count):
 * `n_ctrl` control points in `ctrl` (`n_ctrl * dim` doubles, point after point, in group axis
 * order and user units, absolute; `options->relative` is ignored), `n_ctrl` weights (finite
 * and positive) and `n_knots` = `n_ctrl + degree + 1` knots (clamped, non-decreasing). The
 * curve must start where the group's path is (`MC_ERR_NURBS_START`). A curve the library
 * refuses gets the code the card gives for the same fault (`MC_ERR_NURBS_DEGREE`, `_DIMENSION`,
 * `_CTRL_COUNT`, `_KNOT_COUNT`, `_KNOTS_DECREASING`, `_KNOT_MULTIPLICITY`, `_NOT_CLAMPED`,
 * `_WEIGHT`, `_POINT`). `motion` may be NULL; otherwise it receives the move to wait for.
 *
 * Blocks while the curve is sent: a begin, data entries of up to 12 values and an end, each
 * answered by the card (at most 32 entries in flight; a long curve takes many round trips),
 * not until the move is done.
 */
mc_result mc_group_move_nurbs(mc_card card,
                              uint32_t group,
                              uint32_t degree,
                              const double *ctrl,
                              size_t n_ctrl,
                              uint32_t dim,
                              const double *weights,
                              const double *knots,
                              size_t n_knots,
                              const struct mc_nurbs_feed *feed,
                              const struct mc_move_options *options,
                              struct mc_group_motion *motion);

/**
 * A path longer than the card holds (`move_nurbs_path`): the `ncurves` curves of `curves`,
 * each as the arguments of `mc_group_move_nurbs`, queued one after another behind the moves
 * already queued. Every curve is checked before anything is sent (a refused curve's message
 * names its index). Each piece starts and ends at rest (Yeh's planner runs per curve), and
 * each must start where the previous one ends. `MC_ERR_UNSUPPORTED` for an empty path (`curves`
 * may then be NULL). `motion` may be NULL; otherwise it receives the last piece's move.
 *
 * Blocks while the pieces are sent, and whenever the group's queue is full, until an earlier
 * piece is done (up to `timeout_ms` for each such wait: `MC_ERR_TIMEOUT`); returns when the
 * last piece is queued, not when it is done.
 */
mc_result mc_group_move_nurbs_path(mc_card card,
                                   uint32_t group,
                                   const struct mc_nurbs_curve *curves,
                                   size_t ncurves,
                                   const struct mc_nurbs_feed *feed,
                                   uint32_t timeout_ms,
                                   struct mc_group_motion *motion);

/**
 * A clamped knot vector with uniform interior knots for `n_ctrl` control points of `degree`
 * (`n_ctrl + degree + 1` knots from 0 to 1; the SDK's `clamped_uniform_knots`). Writes the
 * knots to `knots` and their count to `*needed`; when `len` is too small, only `*needed` and
 * `MC_ERR_BUFFER_TOO_SMALL` (`knots` may be NULL when `len` is 0, to ask for the count).
 * `MC_ERR_NURBS_DEGREE` for a degree outside 1..5, `MC_ERR_NURBS_CTRL_COUNT` for fewer than
 * `degree + 1` or more than 1024 control points. Never blocks.
 */
mc_result mc_nurbs_clamped_uniform_knots(size_t n_ctrl,
                                         uint32_t degree,
                                         double *knots,
                                         size_t len,
                                         size_t *needed);

/**
 * Wait until a group move is done: the last move of a queue when the group is at rest and in
 * position, an earlier one when the next move takes over. `MC_ERR_ABORTED` when a halt, stop,
 * disable or fault ended it, `MC_ERR_TIMEOUT` after `timeout_ms` (0: only look). A move can be
 * waited for more than once. `MC_ERR_BAD_HANDLE` for a motion not started on this card (the
 * last 1024 group motions are kept). Blocks.
 */
mc_result mc_group_motion_wait(mc_card card, struct mc_group_motion motion, uint32_t timeout_ms);

/**
 * Wait for the last move queued on this group by this process, as `mc_group_motion_wait`.
 * `MC_ERR_NO_MOTION` when none was queued since the card was opened (nothing to
 * wait for). Blocks.
 */
mc_result mc_group_wait_done(mc_card card, uint32_t group, uint32_t timeout_ms);

/**
 * A consistent snapshot of a group's status (state, queue, active move, path position and
 * feed in counts). Does not wait for the card, as `mc_get_status`.
 */
mc_result mc_group_get_status(mc_card card, uint32_t group, struct mc_group_status *status);

/**
 * Shin's Table 1 for the x and y axes: rapid bell 35 ms, cutting linear 30 ms, jog exponential
 * 50 ms (the card's default). Never blocks.
 */
mc_result mc_filter_settings_shin_table1(struct mc_filter_settings *settings);

/**
 * Shin's Table 1 for the z axis: rapid bell 85 ms, cutting linear 30 ms, jog exponential 40 ms.
 * Never blocks.
 */
mc_result mc_filter_settings_shin_table1_z(struct mc_filter_settings *settings);

/**
 * One filter (`MC_FILTER_KIND_` value; unknown: `MC_ERR_BAD_CONFIG`) with time constant `tau`
 * (s) for every feed type. Nothing is checked until `mc_axis_set_filters`. Never blocks.
 */
mc_result mc_filter_settings_all(uint32_t kind, double tau, struct mc_filter_settings *settings);

/**
 * Set an axis's post-interpolation acc/dec filters (used by groups with
 * `MC_GROUP_ACCDEC_POST` or `_BOTH`; the move's feed type picks one). Refused while the filters
 * still hold distance (`MC_ERR_FILTER_BUSY`); an unknown `MC_FILTER_KIND_` is
 * `MC_ERR_BAD_CONFIG`. Blocks until the card answers.
 */
mc_result mc_axis_set_filters(mc_card card,
                              uint32_t axis,
                              const struct mc_filter_settings *settings);

/**
 * The PD+ gains and drive model of Yeh's die bonder (Table 1), axis 0 (X) or 1 (Y), in volts
 * (`MC_ERR_BAD_AXIS` for any other axis). Never blocks.
 */
mc_result mc_pdplus_settings_die_bonder(uint32_t axis, mc_pdplus_settings *settings);

/**
 * Switch an axis to the PD+ servo law with these gains and drive model (NaN or infinity:
 * `MC_ERR_NOT_FINITE`; the card refuses gains or a model it cannot use, and a `umax` above the
 * axis's `dac_limit_v`: `MC_ERR_BAD_CONFIG`). Needed on every group axis for a
 * saturation-aware NURBS feed. Blocks until the card answers.
 */
mc_result mc_axis_configure_pdplus(mc_card card, uint32_t axis, const mc_pdplus_settings *settings);

/**
 * Home group `group` in stages and wait up to `timeout_ms`. The order is `nstages` stages of
 * group axis indices (0: the group's first axis, X), one after another in `axes`, stage k
 * holding `stage_sizes[k]` of them: `axes = {2, 0, 1}`, `stage_sizes = {1, 2}` homes Z, then X
 * and Y together. `nstages` 0 (the pointers may be NULL): the group's configured order (the
 * configuration file's `home_order`). Each axis homes with its own homing settings; a
 * member that is a gantry's master homes its gantry. `*stages_run` (may be NULL): the stages
 * run. The group is in GroupHoming until it ends, then GroupStandby. Refused:
 * `MC_ERR_HOME_AXIS` (an index the group does not have), `MC_ERR_HOME_TWICE` (an axis twice),
 * `MC_ERR_HOME_STAGE` (an empty stage; or no order and none configured), `MC_ERR_BAD_CONFIG`
 * (more than 8 stages), `MC_ERR_GROUP_DISABLED`, `MC_ERR_INVALID_STATE` (not at rest),
 * `MC_ERR_AXIS_BUSY`, and each axis's homing refusals. `MC_ERR_HOMING_FAILED` when it failed
 * as a whole (the message names the axis and its error; the group's other members were
 * halted and the group is at rest), `MC_ERR_TIMEOUT`.
 */
mc_result mc_group_home(mc_card card,
                        uint32_t group,
                        const uint32_t *axes,
                        const uint32_t *stage_sizes,
                        size_t nstages,
                        uint32_t timeout_ms,
                        uint32_t *stages_run);

/**
 * Select auxiliary encoder `input` as the handwheel of `axis`: each detent (`detent`
 * auxiliary counts, 1..1024, usually `MC_HANDWHEEL_DEFAULT_DETENT`) moves the axis by `ratio`
 * encoder counts (x1, x10, x100; 1 <= |ratio| <= 10000, negative: the other way; on an axis
 * whose scale is negative the ratio is negated, so the wheel turns the axis forward in user
 * units). The axis follows within its jog limits (`jog_max_vel`, `jog_accel`, `jog_jerk` of
 * `mc_axis_settings`), in SynchronizedMotion; turned faster, the excess is dropped: once the
 * wheel stops, the axis stops within its stop distance from `jog_max_vel` plus one servo
 * period at it. Once homed with soft limits on, the wheel stops the axis at a soft limit.
 * From Standstill, or taking over a move or velocity mode (aborted; the wheel starts where the
 * jog ramp stops the axis), or on the axis's own handwheel (a new input, ratio or detent: the
 * motion goes on, and `*motion` is the first selection's). An input selected for another axis
 * is handed over: that axis goes on to where the wheel put it, its motion done. `motion` (may
 * be NULL) receives the motion, done once the handwheel is let go (`mc_handwheel_off`, or its
 * input handed over) and the axis in position; `MC_ERR_ABORTED` after a halt, stop or fault.
 * Refused: `MC_ERR_HANDWHEEL_INPUT` (no such input), `MC_ERR_HANDWHEEL_RATIO` (a ratio of 0 or
 * beyond 10000, a detent outside 1..1024), `MC_ERR_AXIS_GROUPED`, `MC_ERR_AXIS_DISABLED`,
 * `MC_ERR_INVALID_STATE` (homing, stopping, geared, ErrorStop). Blocks until the card answers.
 */
mc_result mc_handwheel_select(mc_card card,
                              uint32_t axis,
                              uint32_t input,
                              int32_t ratio,
                              uint32_t detent,
                              struct mc_motion *motion);

/**
 * Let go of the handwheel of `axis`: the axis goes on to where the wheel put it, and the
 * handwheel's motion is done there. `MC_ERR_INVALID_STATE` when no handwheel drives the axis.
 * Blocks until the card answers.
 */
mc_result mc_handwheel_off(mc_card card, uint32_t axis);

/**
 * The homing configuration the card loads at boot: method 37 (the current position), search
 * at 20000 counts/s, creep at 1000 counts/s, 200000 counts/s², 2e7 counts/s³, no offset, a 60 s
 * timeout, 1e6 counts of search, the index within 12000 counts, a hard stop at 200 counts of
 * following error held 20 ms, an index channel, and the axis ending at the home point. Never
 * blocks.
 */
mc_result mc_homing_settings_default(mc_homing_settings *settings);

/**
 * Write an axis's homing configuration and have the card apply it: an unknown method, or an
 * index method without `MC_HOMING_FLAG_INDEX`, is `MC_ERR_HOMING_METHOD`; a value that is not
 * finite `MC_ERR_NOT_FINITE`; one out of range `MC_ERR_BAD_CONFIG` or `MC_ERR_LIMIT_RANGE`.
 * Blocks until the card answers.
 */
mc_result mc_configure_homing(mc_card card, uint32_t axis, const mc_homing_settings *settings);

/**
 * MC_Home from standstill with the configured method: the home point will read `position`
 * (user units) plus the configured home offset. `mc_motion_wait` on `*motion` (may be NULL;
 * `mc_wait_done` works too) gives the actual position once homed and in position, or
 * `MC_ERR_HOMING_FAILED` (switch, hard stop or index not found, or the timeout; an
 * `MC_EVENT_HOMING_FAILED` event says why, and the axis is at rest, not homed), or
 * `MC_ERR_ABORTED` (`mc_halt`, `mc_stop`, a safety stop). While the axis homes, moves and jogs
 * are `MC_ERR_AXIS_HOMING`. Blocks until the card answers.
 */
mc_result mc_home(mc_card card, uint32_t axis, double position, struct mc_motion *motion);

/**
 * MC_SetPosition: the actual and commanded positions become `position` (user units; with
 * `flags` `MC_SET_POSITION_RELATIVE`, they move by it) without moving the axis, and it counts
 * as homed (soft limits take effect). At standstill or disabled (`MC_ERR_INVALID_STATE`
 * otherwise, `MC_ERR_AXIS_HOMING` while it homes); other flag bits are `MC_ERR_BAD_CONFIG`.
 * Blocks until the card answers.
 */
mc_result mc_set_position(mc_card card, uint32_t axis, double position, uint32_t flags);

/**
 * The inputs' configuration the card loads at boot: all active high, no debounce, no events.
 * Never blocks.
 */
mc_result mc_io_settings_default(mc_io_settings *settings);

/**
 * Write the inputs' configuration and have the card apply it: a bit beyond the 16 inputs or a
 * debounce over 10000 ticks is `MC_ERR_IO_CONFIG`. Blocks until the card answers.
 */
mc_result mc_configure_io(mc_card card, const mc_io_settings *settings);

/**
 * The debounced inputs, polarity applied (bit i = input i active). Never blocks.
 */
mc_result mc_get_inputs(mc_card card, uint32_t *inputs);

/**
 * Arm compare channel `channel` on `axis`: pulse `output` for `pulse_us` µs when the actual
 * position crosses `position` (user units) in `direction` (`MC_COMPARE_`). A position behind
 * the axis is reported missed. `MC_ERR_COMPARE_BUSY` if the channel is armed or its output is
 * another armed channel's. Blocks until the card answers.
 */
mc_result mc_compare_single(mc_card card,
                            uint32_t axis,
                            uint32_t channel,
                            uint32_t output,
                            uint32_t pulse_us,
                            double position,
                            uint32_t direction_);

/**
 * Layout 1.13, a rotary axis: pulse `output` at every crossing of `position` (a place on the
 * turn, 0 <= position < modulo, user units) in `direction`, on every turn, until
 * `mc_compare_disarm`. A linear axis or a position off the turn: `MC_ERR_COMPARE_TURN`.
 * Blocks until the card answers.
 */
mc_result mc_compare_single_each_turn(mc_card card,
                                      uint32_t axis,
                                      uint32_t channel,
                                      uint32_t output,
                                      uint32_t pulse_us,
                                      double position,
                                      uint32_t direction_);

/**
 * Arm a linear series: `count` positions from `start`, `pitch` (> 0, user units) apart in
 * `direction` (`MC_COMPARE_POSITIVE` or `_NEGATIVE`). On a rotary axis (layout 1.13) the
 * positions wrap into the turn and must fit one (`MC_ERR_COMPARE_TURN`), each fired at the
 * next crossing after the one before. Blocks until the card answers.
 */
mc_result mc_compare_series(mc_card card,
                            uint32_t axis,
                            uint32_t channel,
                            uint32_t output,
                            uint32_t pulse_us,
                            double start,
                            double pitch,
                            uint32_t count,
                            uint32_t direction_);

/**
 * Layout 1.13, a rotary axis: the series of `mc_compare_series` on every turn, endless until
 * `mc_compare_disarm`: `count` positions from `start` (0 <= start < modulo), `pitch` apart in
 * `direction`, wrapped into the turn, with count * pitch <= modulo; `count` 0: a whole turn of
 * pitches (floor(modulo / pitch)). Each place fires at every crossing, whichever the axis
 * comes to (back and forth as well). A linear axis or a series that does not fit the turn:
 * `MC_ERR_COMPARE_TURN`. Blocks until the card answers.
 */
mc_result mc_compare_series_each_turn(mc_card card,
                                      uint32_t axis,
                                      uint32_t channel,
                                      uint32_t output,
                                      uint32_t pulse_us,
                                      double start,
                                      double pitch,
                                      uint32_t count,
                                      uint32_t direction_);

/**
 * Arm the channel's table (positions queued before with `mc_compare_push`, or after), in
 * `direction`; an `MC_EVENT_COMPARE` with code `MC_COMPARE_LOW_WATER` when the queue falls to
 * `low_water` (0: none). Blocks until the card answers.
 */
mc_result mc_compare_table(mc_card card,
                           uint32_t axis,
                           uint32_t channel,
                           uint32_t output,
                           uint32_t pulse_us,
                           uint32_t low_water,
                           uint32_t direction_);

/**
 * Queue `n` positions (user units, strictly monotonic in `direction`) in the channel's table
 * and write the room left to `*room` (may be NULL). More than `MC_COMPARE_TABLE_LEN` at once
 * is `MC_ERR_COMPARE_FULL` before anything is sent; a table that fills up is
 * `MC_ERR_COMPARE_FULL` (the entries of 12 before it stay queued); out of order
 * `MC_ERR_COMPARE_ORDER`. Blocks until the card answers each entry.
 */
mc_result mc_compare_push(mc_card card,
                          uint32_t axis,
                          uint32_t channel,
                          uint32_t direction_,
                          const double *positions,
                          size_t n,
                          size_t *room);

/**
 * Disarm the channel, drop its table, end its pulse. Blocks until the card answers.
 */
mc_result mc_compare_disarm(mc_card card, uint32_t axis, uint32_t channel);

/**
 * The channel's status, positions in `axis`'s user units. Never blocks.
 */
mc_result mc_compare_get_status(mc_card card,
                                uint32_t axis,
                                uint32_t channel,
                                struct mc_compare_info *status);

/**
 * MC_TouchProbe: arm probe `channel` to capture `axis`'s position at `trigger` (a re-arm
 * restarts it). A bad input, no edge, or a window with `window_lo > window_hi` is
 * `MC_ERR_PROBE_INPUT`. Blocks until the card answers.
 */
mc_result mc_touch_probe(mc_card card,
                         uint32_t axis,
                         uint32_t channel,
                         const struct mc_probe_trigger *trigger);

/**
 * MC_AbortTrigger. Blocks until the card answers.
 */
mc_result mc_abort_trigger(mc_card card, uint32_t axis, uint32_t channel);

/**
 * The probe's status, positions in `axis`'s user units. Never blocks.
 */
mc_result mc_probe_get_status(mc_card card,
                              uint32_t axis,
                              uint32_t channel,
                              struct mc_probe_info *status);

/**
 * Wait up to `timeout_ms` (emulated time on a stepped sim) for capture number `n` (1, 2, …
 * since the arm) and write its position (user units). `MC_ERR_TIMEOUT` if it does not come.
 * Blocks.
 */
mc_result mc_probe_wait(mc_card card,
                        uint32_t axis,
                        uint32_t channel,
                        uint32_t n,
                        uint32_t timeout_ms,
                        double *position);

/**
 * Stepped sim: drive input `input`'s pin to `high` (nonzero) now. `MC_ERR_UNSUPPORTED` on any
 * other card. Never blocks.
 */
mc_result mc_sim_set_input(mc_card card, uint32_t input, uint32_t high);

/**
 * Stepped sim: drive input `input` from a sensor on `axis`'s travel that is active at and
 * above (`active_above` nonzero) or at and below shaft position `at` (counts): a part a touch
 * probe hits. `MC_ERR_UNSUPPORTED` on any other card. Never blocks.
 */
mc_result mc_sim_set_sensor(mc_card card,
                            uint32_t input,
                            uint32_t axis,
                            double at,
                            uint32_t active_above);

/**
 * Every card reachable from this process: `card-emu` processes (`emu:`), UIO devices and PCI
 * functions with the card's IDs, in that order, each read without disturbing a host that
 * holds it (as the Rust SDK lists them). Writes the cards to `cards` and their count to
 * `*needed`; when `len` is too small, only `*needed` and `MC_ERR_BUFFER_TOO_SMALL` (`cards`
 * may be NULL when `len` is 0, to ask for the count; cards can come and go between two calls:
 * ask again on `MC_ERR_BUFFER_TOO_SMALL`). A card found but not read is listed with its
 * `error`. `MC_ERR_IO` when /proc cannot be read. Blocks while each `emu:` card answers (a
 * fraction of a millisecond each, at most 5 s for one that does not).
 */
mc_result mc_list_cards(struct mc_card_listing *cards, size_t len, size_t *needed);

/**
 * MC_MoveAbsolute, MC_MoveRelative or MC_MoveAdditive (`kind`: `MC_MOVE_KIND_ABSOLUTE`,
 * `_RELATIVE`, `_ADDITIVE`) with a PLCopen buffer mode (`MC_BUFFER_ABORTING`,
 * `MC_BUFFER_BUFFERED`). From rest the move is the card's time-optimal S-curve with the four
 * jerks of `*limits`; from motion it is time-optimal from the current state with one jerk,
 * the smallest of the four. An unknown kind or mode is `MC_ERR_BAD_CONFIG`. `motion` may be
 * NULL. Blocks until the card answers.
 */
mc_result mc_move(mc_card card,
                  uint32_t axis,
                  uint32_t kind,
                  double value,
                  const struct mc_move_limits *limits,
                  uint32_t buffer_mode,
                  struct mc_motion *motion);

/**
 * MC_MoveAdditive (Aborting): by `distance` from the target of the last move; otherwise as
 * `mc_move_absolute`.
 */
mc_result mc_move_additive(mc_card card,
                           uint32_t axis,
                           double distance,
                           const struct mc_move_limits *limits,
                           struct mc_motion *motion);

/**
 * MC_MoveVelocity: run at the signed `velocity` (user units/s), reached within `*limits` from
 * the current state (state ContinuousMotion); call again to change it, end it with `mc_halt`
 * or `mc_stop`. `mc_motion_wait_in_velocity` waits for the velocity; the motion is never
 * done, only aborted. `motion` may be NULL. Blocks until the card answers.
 */
mc_result mc_move_velocity(mc_card card,
                           uint32_t axis,
                           double velocity,
                           const struct mc_velocity_limits *limits,
                           struct mc_motion *motion);

/**
 * Jog: velocity mode at the signed `velocity` (user units/s) with the axis's jog limits
 * (`jog_max_vel`, `jog_accel`, `jog_jerk` of `mc_axis_settings`); beyond `jog_max_vel` it is
 * `MC_ERR_OUT_OF_RANGE`. Releasing the button is `mc_jog_release`. `motion` may be NULL.
 */
mc_result mc_jog(mc_card card, uint32_t axis, double velocity, struct mc_motion *motion);

/**
 * Releasing the jog button: MC_Halt at the axis's jog deceleration and jerk. `motion` (may be
 * NULL) receives the halt.
 */
mc_result mc_jog_release(mc_card card, uint32_t axis, struct mc_motion *motion);

/**
 * MC_SetOverride: scale the axis's velocity by `factor`, 0.0 to 2.0 (0 % to 200 %; else
 * `MC_ERR_OVERRIDE_RANGE`), planned from the current state within the acceleration and jerk
 * limits. 0 holds the axis still in its motion state; a factor above 0 resumes.
 */
mc_result mc_set_override(mc_card card, uint32_t axis, double factor);

/**
 * Wait until a buffered move starts (PLCopen Active). `target` may be NULL; otherwise it
 * receives the move's target (velocity mode: its velocity). `MC_ERR_ABORTED` if it was
 * aborted first, `MC_ERR_TIMEOUT` after `timeout_ms`. Blocks.
 */
mc_result mc_motion_wait_active(mc_card card,
                                struct mc_motion motion,
                                uint32_t timeout_ms,
                                double *target);

/**
 * Wait until velocity mode reaches its velocity (PLCopen InVelocity). `velocity` may be NULL;
 * otherwise it receives the velocity. `MC_ERR_ABORTED` if it was aborted first,
 * `MC_ERR_TIMEOUT` after `timeout_ms`. Blocks.
 */
mc_result mc_motion_wait_in_velocity(mc_card card,
                                     struct mc_motion motion,
                                     uint32_t timeout_ms,
                                     double *velocity);

/**
 * Path settings for `naxes` axes (1..8, else `MC_ERR_BAD_AXIS`) with the same limits:
 * look-ahead 256 segments, no low-water event, tangential limits from the axes' (0), chords
 * fitted into curves. Nothing is checked until `mc_group_configure_path`. Never blocks.
 */
mc_result mc_path_settings_uniform(uint32_t naxes,
                                   double vmax,
                                   double amax,
                                   double jmax,
                                   struct mc_path_settings *settings);

/**
 * Configure a group's path: its look-ahead, low-water mark and limits. The group must be
 * configured (`MC_ERR_GROUP_DISABLED`) and its path idle, nothing queued and at rest
 * (`MC_ERR_PATH_BUSY`). `naxes` must be the group's axis count (`MC_ERR_BAD_AXIS`); each axis
 * limit finite and > 0 (`MC_ERR_NOT_FINITE`, `MC_ERR_NON_POSITIVE_LIMIT`); the card refuses a
 * look-ahead outside 1..`MC_PATH_SEGMENTS` or a low-water mark above it (`MC_ERR_BAD_CONFIG`),
 * a planner period that is not a number (`MC_ERR_NOT_FINITE`) or outside 0..0.01 s
 * (`MC_ERR_OUT_OF_RANGE`), and limits it cannot run at its servo rate (`MC_ERR_LIMIT_RANGE`).
 * Blocks until the card answers.
 */
mc_result mc_group_configure_path(mc_card card,
                                  uint32_t group,
                                  const struct mc_path_settings *settings);

/**
 * The path configuration the card holds for a group (read back from the card: its reset
 * values until the first `mc_group_configure_path`), converted to user units with the scales
 * in force now; `naxes` is the group's axis count, the unused limits 0. The group must be
 * configured (`MC_ERR_GROUP_DISABLED`). Blocks until the card answers (layout 1.8: the
 * settings are read back with a command).
 */
mc_result mc_group_get_path_settings(mc_card card,
                                     uint32_t group,
                                     struct mc_path_settings *settings);

/**
 * Free segments in a group's path buffer (`MC_PATH_SEGMENTS` when idle). Does not wait for
 * the card, as `mc_group_get_status`.
 */
mc_result mc_group_path_free(mc_card card, uint32_t group, uint32_t *free);

/**
 * Pause a group's path at the end of a segment: it comes to rest at the end of the first
 * segment it can stop at within its limits from where it is (an exact stop or a dwell's end
 * ahead, or the first segment end beyond its braking distance; with nothing queued and at
 * rest, at once), and holds there. The end of a segment followed by a blend is the blend's
 * middle, within the segment's tolerance of its programmed end. Nothing queued changes and
 * more may be queued; `mc_group_path_resume` goes on along the same path. The card posts
 * `MC_EVENT_PATH_PAUSED` (value: the segment's id) on coming to rest. Blocks until the card
 * answers.
 */
mc_result mc_group_path_pause(mc_card card, uint32_t group);

/**
 * End a pause (`mc_group_path_pause`): the path goes on from the pause point (asked before
 * it got there, it does not stop). Blocks until the card answers.
 */
mc_result mc_group_path_resume(mc_card card, uint32_t group);

/**
 * Where a group's pause is: `*state` `MC_PATH_PAUSE_*`, `*id` (may be NULL) the id of the
 * segment it ended when paused (0 when none ran; else 0). From the status: does not wait
 * for the card.
 */
mc_result mc_group_path_pause_state(mc_card card, uint32_t group, uint32_t *state, uint32_t *id);

/**
 * A line to `target` (`n` values, one per group axis, user units; at most 8, else
 * `MC_ERR_BAD_AXIS`) at `feed`, blended into the segment before within `tolerance` of the
 * corner (`MC_PATH_BUFFER_BLEND_LOW`, `MC_PATH_TRANSITION_MAX_DEVIATION`; 0: an exact stop),
 * absolute, not last. Nothing else is checked until it is queued. Never blocks.
 */
mc_result mc_path_segment_line(uint32_t id,
                               const double *target,
                               size_t n,
                               double feed,
                               double tolerance,
                               struct mc_path_segment *segment);

/**
 * A normal-vector arc segment (`MC_SEGMENT_ARC_NORMAL`, layout 1.12) in the plane of group
 * axes `axes[3]` with `normal[3]`, around `centre[3]` to `end[3]` (on those axes) at `feed`,
 * blended as `mc_path_segment_line`; the other axes stay (set `target` and `naxes` for a
 * helix, `rise` for a rise along the normal). Never blocks.
 *
 * # Safety
 * `axes`, `normal`, `centre` and `end` are NULL or point to 3 readable values each;
 * `segment` is NULL or valid for writes.
 */
mc_result mc_path_segment_arc_normal(uint32_t id,
                                     const uint32_t *axes,
                                     const double *normal,
                                     const double *centre,
                                     const double *end,
                                     double feed,
                                     double tolerance,
                                     struct mc_path_segment *segment);

/**
 * An arc in `plane` (`MC_ARC_PLANE_`) described by `*arc` (as `mc_group_move_circular`), a
 * helix when `nhelix` targets of the group's other axes are given (`helix` may be NULL when
 * `nhelix` is 0), blended as `mc_path_segment_line`. Never blocks.
 */
mc_result mc_path_segment_arc(uint32_t id,
                              const struct mc_arc *arc,
                              uint32_t plane,
                              const double *helix,
                              size_t nhelix,
                              double feed,
                              double tolerance,
                              struct mc_path_segment *segment);

/**
 * A NURBS curve `*curve` (as the arguments of `mc_group_move_nurbs`) at `feed`, blended into
 * the segment before within `tolerance` of the corner (as `mc_path_segment_line`), run within
 * `fit_tolerance` of the curve, absolute, not last. The segment keeps `curve`'s array
 * pointers: they must stay readable until it is queued. Nothing else is checked until then.
 * Never blocks.
 */
mc_result mc_path_segment_nurbs(uint32_t id,
                                const struct mc_nurbs_curve *curve,
                                double feed,
                                double tolerance,
                                double fit_tolerance,
                                struct mc_path_segment *segment);

/**
 * A dwell: an exact stop, then a wait of `seconds`. Never blocks.
 */
mc_result mc_path_segment_dwell(uint32_t id, double seconds, struct mc_path_segment *segment);

/**
 * An output action: set (`on` non-zero) or clear `output` when the next motion segment queued
 * after it starts, ends, or has run `distance` (`at`: `MC_OUTPUT_AT_`). Never blocks.
 */
mc_result mc_path_segment_output(uint32_t output,
                                 uint32_t on,
                                 uint32_t at,
                                 double distance,
                                 struct mc_path_segment *segment);

/**
 * Queue one item in a group's path and wait for the card's answer (not for the motion). The
 * library checks the item first with the card's rules: a non-finite value is
 * `MC_ERR_NOT_FINITE`, a feed or dwell <= 0 `MC_ERR_NON_POSITIVE_LIMIT`, a negative tolerance
 * or distance `MC_ERR_OUT_OF_RANGE`, `naxes` not the group's count `MC_ERR_BAD_AXIS`, an
 * unknown buffer, transition or output point `MC_ERR_PATH_MODE`, an output >=
 * `MC_CARD_OUTPUTS` `MC_ERR_PATH_OUTPUT`. The card refuses a line of length zero
 * (`MC_ERR_PATH_ZERO_LENGTH`), a bad arc (as `mc_group_move_circular`), a segment while group
 * moves run (`MC_ERR_PATH_BUSY`), a full buffer (`MC_ERR_QUEUE_FULL`; `mc_group_path_stream`
 * waits for room instead), a group with post-interpolation filters
 * (`MC_ERR_INCOMPATIBLE_MODE`), a group halting or stopping (`MC_ERR_INVALID_STATE`).
 *
 * `motion` may be NULL; otherwise it receives the segment's motion: done when the path has
 * left it, or, when it is the last queued, once the path is at rest in position at its end
 * (wait with `mc_group_motion_wait`); aborted by a halt, stop, fault or an Aborting segment.
 * An output action has no motion: it receives seq 0. Blocks until the card answers.
 */
mc_result mc_group_path_push(mc_card card,
                             uint32_t group,
                             const struct mc_path_segment *segment,
                             struct mc_group_motion *motion);

/**
 * Queue an output action (`mc_path_segment_output`, then `mc_group_path_push`): set (`on`
 * non-zero) or clear `output` (0..`MC_CARD_OUTPUTS` - 1, else `MC_ERR_PATH_OUTPUT`) when the
 * next motion segment queued after it starts, ends, or has run `distance` (`at`:
 * `MC_OUTPUT_AT_`). At most 8 actions may wait for their segment (`MC_ERR_PATH_OUTPUT`).
 * Blocks until the card answers.
 */
mc_result mc_group_path_output(mc_card card,
                               uint32_t group,
                               uint32_t output,
                               uint32_t on,
                               uint32_t at,
                               double distance);

/**
 * Stream `n` items (`segments`, may be NULL when `n` is 0) into a group's path: up to 48
 * commands in flight, never more segments than the card's buffer has room for, so a path
 * longer than `MC_PATH_SEGMENTS` streams while it runs. Every item is checked by the library
 * first, before anything is sent (as `mc_group_path_push`); the first refused item stops the
 * stream with its code, and the items before it are queued and run. An item the library
 * refuses stops the stream before it is sent. An item the card refuses (a line of length
 * zero, a bad arc, `MC_ERR_PATH_BUSY`, ...) is answered while the items behind it are on
 * their way: the stream waits for all their answers, and up to 47 of them may have been
 * queued after all (then `*accepted` exceeds the refused item's index); put such an item
 * last, or halt the group (`mc_group_halt`) to drop them.
 *
 * `progress` (may be NULL) is called with `user` on this thread after each item sent.
 * `accepted` (may be NULL) always receives how many items the card accepted (an exception
 * to "outputs only on success"): on success `n`; after a refusal or a failure, the items
 * the card took (0 when nothing was sent). `last` (may be NULL) receives, on success, the motion of the last segment: done
 * once the path is at rest at its end (`mc_group_motion_wait`); seq 0 when the items hold no
 * segment.
 *
 * Blocks while the items are sent, and whenever the buffer is full, until the running path
 * makes room; returns when the last item is accepted, not when the path is done.
 */
mc_result mc_group_path_stream(mc_card card,
                               uint32_t group,
                               const struct mc_path_segment *segments,
                               size_t n,
                               mc_path_progress_callback progress,
                               void *user,
                               size_t *accepted,
                               struct mc_group_motion *last);

/**
 * Start streaming `n` items (`segments`, may be NULL when `n` is 0) into a group's path from
 * a thread of the library, as `mc_group_path_stream` streams them, and return at once with
 * its handle in `*streamer`. Every item is checked and copied first (a NURBS item's arrays
 * too: the caller's memory is not read after this call): an item the library refuses is
 * returned with its code (the message names the item) and nothing is sent. The thread calls
 * no application code. Watch it with `mc_path_streamer_progress`, stop it with
 * `mc_path_streamer_cancel`, and end it with `mc_path_streamer_join` (which every handle
 * needs: it frees it). Blocks only while the items are checked.
 */
mc_result mc_group_path_stream_start(mc_card card,
                                     uint32_t group,
                                     const struct mc_path_segment *segments,
                                     size_t n,
                                     mc_path_streamer *streamer);

/**
 * The stream's progress (`sent` and `accepted` items, the card's `done` and `queued`
 * segments) and, in `*finished` (may be NULL), 1 once its thread has ended (everything sent
 * and answered, cancelled, or stopped by a refusal: `mc_path_streamer_join` says which), else
 * 0. Never blocks (it reads the card's window).
 */
mc_result mc_path_streamer_progress(mc_path_streamer streamer,
                                    struct mc_path_progress *progress,
                                    uint32_t *finished);

/**
 * Stop sending: the items not sent yet are dropped, what the card accepted stays queued and
 * runs (`mc_group_halt` stops that too). The thread ends once the commands in flight are
 * answered; `mc_path_streamer_join` then returns `MC_ERR_CANCELLED`. Never blocks.
 */
mc_result mc_path_streamer_cancel(mc_path_streamer streamer);

/**
 * Wait for the stream's thread to end and free the handle (always, whatever it returns).
 * Returns the stream's result as `mc_group_path_stream` does: `MC_OK` when every item was
 * accepted (`*last`, may be NULL: the motion of the last segment, seq 0 when there was
 * none), `MC_ERR_CANCELLED` after `mc_path_streamer_cancel`, or the code of the item that
 * stopped it (the message names it). `accepted` (may be NULL) always receives how many
 * items the card accepted. Blocks until the thread ends (at most until the items are sent,
 * waiting for room as the path runs).
 */
mc_result mc_path_streamer_join(mc_path_streamer streamer,
                                size_t *accepted,
                                struct mc_group_motion *last);

/**
 * The card's digital outputs as it drives them (bit i = output i, `MC_CARD_OUTPUTS` of them):
 * set by `mc_set_outputs` or by a path's output actions. Never blocks.
 */
mc_result mc_get_outputs(mc_card card, uint32_t *outputs);

/**
 * Set the outputs in `mask` to the bits of `value` now (the others keep theirs). A bit at or
 * above `MC_CARD_OUTPUTS` in either is `MC_ERR_PATH_OUTPUT`. Blocks until the card answers.
 */
mc_result mc_set_outputs(mc_card card, uint32_t mask, uint32_t value);

/**
 * Open a PT/PVT stream on `axis` at its commanded position (standstill), at rest, time 0:
 * `mode` `MC_PVT_MODE_`, `limits`, a low-water event (`MC_EVENT_PVT`,
 * `MC_PVT_EVENT_LOW_WATER`) once `low_water` points or fewer are left (0: none). Blocks until
 * the card answers.
 */
mc_result mc_pvt_begin(mc_card card,
                       uint32_t axis,
                       uint32_t mode,
                       const struct mc_pvt_limits *limits,
                       uint32_t low_water);

/**
 * Append `n` points (at most `MC_PVT_LEN`) to the stream; with `last` nonzero the last of them
 * ends it (PVT: at velocity 0). `free` (may be NULL) receives the points still free on the
 * card. A refused point (`MC_ERR_PVT_LIMIT`, `MC_ERR_PVT_TIME`, `MC_ERR_NOT_FINITE`,
 * `MC_ERR_OUT_OF_RANGE`, `MC_ERR_QUEUE_FULL`, `MC_ERR_PVT_SEQUENCE`) is named in the error
 * message ("PT/PVT point I ..."); the points before it were queued. Blocks until the card
 * answers.
 */
mc_result mc_pvt_push(mc_card card,
                      uint32_t axis,
                      const struct mc_pvt_point *points,
                      size_t n,
                      uint32_t last,
                      size_t *free);

/**
 * Run `axis`'s stream: `mc_motion_wait` on `*motion` (may be NULL) returns once the last
 * point is reached and the axis is in position, or `MC_ERR_ABORTED` if the stream ran dry
 * (`MC_PVT_EVENT_STARVED`; the axis stops on its stop ramp) or a halt, stop or safety stop
 * ended it. Blocks until the card answers.
 */
mc_result mc_pvt_start(mc_card card, uint32_t axis, struct mc_motion *motion);

/**
 * Points queued in `axis`'s stream and free, as the card published them last tick (either
 * pointer may be NULL). Never blocks.
 */
mc_result mc_pvt_room(mc_card card, uint32_t axis, size_t *queued, size_t *free);

/**
 * Make `axis` a rotary (modulo) axis of `period` user units (for example 360 with a scale in
 * counts per degree): its status's positions, motion done's and probe captures wrap into
 * [0, period) without drift; position compare is turn-aware (layout 1.13: positions in
 * [0, period), `mc_compare_single_each_turn`, `mc_compare_series_each_turn`); soft limits do
 * not apply. At rest only (`MC_ERR_MODULO_BUSY`), and not while an armed compare channel
 * watches the axis (`MC_ERR_COMPARE_TURN`). A
 * period of 0 is `MC_ERR_MODULO_ZERO` (`mc_axis_clear_modulo` makes an axis linear), a
 * negative, non-finite or out-of-range one (1 to 1e11 counts) `MC_ERR_MODULO_RANGE`; the axis
 * needs a positive scale (`MC_ERR_BAD_CONFIG`). A refusal changes nothing.
 */
mc_result mc_axis_set_modulo(mc_card card, uint32_t axis, double period);

/**
 * Make `axis` linear again (its position stays where it is). At rest only
 * (`MC_ERR_MODULO_BUSY`).
 */
mc_result mc_axis_clear_modulo(mc_card card, uint32_t axis);

/**
 * The modulo period the card holds for `axis` (read back), in user units; 0 for a linear
 * axis. `*period` is written on success.
 */
mc_result mc_axis_get_modulo(mc_card card, uint32_t axis, double *period);

/**
 * MC_MoveAbsolute (Aborting) the way `direction` names (`MC_MOVE_DIR_SHORTEST`, `_POSITIVE`,
 * `_NEGATIVE`, `_CURRENT`; another value: `MC_ERR_BAD_CONFIG`). On a modulo axis
 * `target` must be in [0, period) (else `MC_ERR_MODULO_MOVE`); the shortest way takes a tie of
 * half a turn positive, and a target within the in-position window of where the axis is is no
 * turn. On a linear axis only `MC_MOVE_DIR_SHORTEST` (else `MC_ERR_MODULO_MOVE`). Otherwise as
 * `mc_move_absolute`.
 */
mc_result mc_move_absolute_dir(mc_card card,
                               uint32_t axis,
                               double target,
                               uint32_t direction,
                               const struct mc_move_limits *limits,
                               struct mc_motion *motion);

/**
 * Stop (`on` = 0) or resume (non-zero) this process's heartbeat to the card. A stopped
 * heartbeat is a hung host to the card: its watchdog trips after the timeout, every axis makes
 * a category 1 stop, and the trip stays latched until `mc_reset_faults`. On a real-time card a
 * library thread writes the heartbeat; on a stepped sim it beats once per emulated tick, so
 * stepping with the heartbeat off trips the watchdog deterministically. For tests of the
 * watchdog; the heartbeat is on from `mc_open`. Never blocks.
 */
mc_result mc_set_heartbeat(mc_card card, uint32_t on);

/**
 * Set the card's watchdog timeout, µs (default 100000: above the heartbeat gaps of a loaded
 * host without real-time scheduling). The card refuses zero and anything under
 * 1.5 × the library's heartbeat period of 1 ms: `MC_ERR_WATCHDOG_TIMEOUT`. On a `sim` card
 * opened with `MOTIONCARD_SIM_WATCHDOG_MS` set (debugging), a shorter timeout gets that one.
 * Blocks until the card answers.
 */
mc_result mc_set_watchdog_timeout(mc_card card, uint32_t timeout_us);

/**
 * The stop the card's e-stop input makes (`MC_STOP_CATEGORY_`; default 1; any other value is
 * `MC_ERR_BAD_CATEGORY`). Blocks until the card answers.
 */
mc_result mc_set_estop_input_category(mc_card card, uint32_t category);

/**
 * E-stop every axis with the given stop category (`MC_STOP_CATEGORY_`; any other value is
 * `MC_ERR_BAD_CATEGORY`). Latched: moves, enables and resets are refused with
 * `MC_ERR_ESTOP_ACTIVE` until `mc_reset_faults`. Blocks until the card answers.
 */
mc_result mc_estop(mc_card card, uint32_t category);

/**
 * Clear the card-wide latches (watchdog, e-stop), then MC_Reset every axis in ErrorStop.
 * `MC_ERR_CAUSE_ACTIVE` while the cause is still there (no live heartbeat, the e-stop input
 * pressed, an axis's alarm or encoder fault). Axes whose stop removed power end Disabled, the
 * others Standstill. Blocks until the card has answered each command (one, plus one per axis
 * in ErrorStop).
 */
mc_result mc_reset_faults(mc_card card);

/**
 * Set the card's maximum stop time, µs (default 2000000): every stop — halt, stop, the safety
 * stops, starvation — ends within it; a halt whose own ramp would take longer runs on the
 * axis's stop ramp, and a stop still running at the bound loses power (stop reason
 * `MC_STOP_REASON_STOP_TIMEOUT`). 10 ms to 600 s, and every axis's stop ramp from its max
 * velocity must fit: `MC_ERR_STOP_TOO_LONG` otherwise. Blocks until the card answers.
 */
mc_result mc_set_max_stop_time(mc_card card, uint32_t us);

/**
 * The card-wide safety state: watchdog and e-stop latches, heartbeat ticks, protocol errors.
 * Reads the card's window; never blocks.
 */
mc_result mc_get_safety_status(mc_card card, struct mc_safety_status *status);

/**
 * The card's default safety configuration of an axis, in counts: hard limits, amplifier alarm
 * and encoder checks on, soft limits off, limit stops category 1, following error 10,000
 * counts at 10⁶ counts/s and 1,000 at rest, stops at 5·10⁶ counts/s² and 5·10⁸ counts/s³.
 * Never blocks.
 */
mc_result mc_safety_settings_default(struct mc_safety_settings *settings);

/**
 * Write an axis's safety configuration (limits, following error, stop ramp; user units
 * converted through the axis's scale) and have the card apply it. NaN or infinity:
 * `MC_ERR_NOT_FINITE`; an unknown `limit_stop`: `MC_ERR_BAD_CATEGORY`; values the card cannot
 * use (soft limits not increasing, `ferror` under `min_ferror`, a non-positive limit):
 * `MC_ERR_BAD_CONFIG`. Blocks until the card answers.
 */
mc_result mc_configure_safety(mc_card card,
                              uint32_t axis,
                              const struct mc_safety_settings *settings);

/**
 * Why the axis's last motion ended, and the card's timing of its last safety stop: the tick
 * it began, the tick the axis came to rest (`at_rest` 0 while still stopping), the planned
 * ramp. Reads the status block as `mc_get_status` does (`MC_ERR_PROTOCOL` for a stop reason
 * this library does not know); does not wait for the card.
 */
mc_result mc_get_stop_info(mc_card card, uint32_t axis, struct mc_stop_info *info);

/**
 * A configuration to start from: no channels, every tick, immediate trigger, one-shot.
 * Never blocks.
 */
mc_result mc_scope_settings_default(mc_scope_settings *settings);

/**
 * Check the configuration and have the card take it (`MC_ERR_SCOPE_*` for what it refuses;
 * `MC_ERR_SCOPE_STATE` while the scope is armed). Blocks until the card answers.
 */
mc_result mc_scope_configure(mc_card card, const mc_scope_settings *settings);

/**
 * Arm the scope: samples left in the ring are dropped, sampling starts into the pre-trigger
 * history, and the capture waits for its trigger. `seq` (may be NULL) receives the arm's seq.
 * Blocks until the card answers.
 */
mc_result mc_scope_arm(mc_card card, uint32_t *seq);

/**
 * Trigger the waiting scope at its next sample. Blocks until the card answers.
 */
mc_result mc_scope_trigger(mc_card card);

/**
 * Stop the scope (the samples in the ring stay to be read). Blocks until the card answers.
 */
mc_result mc_scope_stop(mc_card card);

/**
 * Take up to `len` samples from the ring, oldest first, into `buf`; `n` receives how many.
 * Never blocks. `buf` may be NULL only when `len` is 0.
 */
mc_result mc_scope_read(mc_card card, struct mc_scope_sample *buf, size_t len, size_t *n);

/**
 * The scope's state, counters included. Never blocks.
 */
mc_result mc_scope_get_info(mc_card card, mc_scope_info *info);

/**
 * Wait up to `timeout_ms` (emulated time on a stepped sim, which is stepped) until the
 * one-shot capture armed last is done, or the scope was stopped; `info` (may be NULL)
 * receives the scope's state then (as `mc_scope_get_info`). `MC_ERR_TIMEOUT` while it still
 * waits for its trigger or captures; `MC_ERR_SCOPE_STATE` when the scope is not armed or
 * runs a continuous capture (which never ends: `mc_scope_stop` it). Reads nothing from the
 * ring: a capture longer than `MC_SCOPE_RING_LEN` samples loses what does not fit unless
 * another thread calls `mc_scope_read` meanwhile. Blocks.
 */
mc_result mc_scope_wait(mc_card card, uint32_t timeout_ms, mc_scope_info *info);

/**
 * The card's default PID+FF tuning, or (accel_per_volt > 0) gains placed for a drive of that
 * many counts/s² per volt at a crossover of `bandwidth_hz` (NaN, infinite or not above 0:
 * `MC_ERR_BAD_CONFIG`). Never blocks.
 */
mc_result mc_pidff_settings_for_drive(double accel_per_volt,
                                      double bandwidth_hz,
                                      mc_pidff_settings *settings);

/**
 * Switch an axis to the PID + feed-forward law with these gains (any state; at rest the switch
 * does not step the output). A gain negative, a derivative cut-off or friction deadband not
 * above 0: `MC_ERR_PIDFF_GAINS`; NaN or infinity: `MC_ERR_NOT_FINITE`. A refusal changes
 * nothing. Blocks until the card answers.
 */
mc_result mc_axis_configure_pidff(mc_card card, uint32_t axis, const mc_pidff_settings *settings);

/**
 * The axis's PID+FF gains as the card holds them (read back): `*active` is 1 and `*settings`
 * the gains when the axis runs PID+FF, else `*active` is 0 and `*settings` all zero. Blocks
 * until the card answers.
 */
mc_result mc_axis_get_pidff(mc_card card,
                            uint32_t axis,
                            mc_pidff_settings *settings,
                            uint32_t *active);

/**
 * Set servo filter `slot` (0..`MC_BIQUADS`-1) of an axis: on the servo law's output, before
 * the DAC clamp, designed by the card at the servo rate (bilinear transform with pre-warping)
 * and checked. Refused, nothing changed: a slot or kind out of range `MC_ERR_FILTER_KIND`, a
 * frequency not above 0 and below half the servo rate `MC_ERR_FILTER_FREQ`, a damping
 * (0..10], depth (-120..0 dB) or raw b (|b| <= 1e6) out of range `MC_ERR_FILTER_PARAM`, a pole
 * not inside the unit circle `MC_ERR_FILTER_UNSTABLE`, NaN or infinity `MC_ERR_NOT_FINITE`.
 * Any state: the filter starts from the steady state of the output of the tick. Blocks until
 * the card answers.
 */
mc_result mc_axis_set_servo_filter(mc_card card,
                                   uint32_t axis,
                                   uint32_t slot,
                                   const struct mc_servo_filter *filter);

/**
 * Empty servo filter `slot` of an axis (an empty slot stays empty; out of range:
 * `MC_ERR_FILTER_KIND`). Blocks until the card answers.
 */
mc_result mc_axis_clear_servo_filter(mc_card card, uint32_t axis, uint32_t slot);

/**
 * Servo filter `slot` of an axis as the card holds it: its kind and parameters, and in
 * `coeffs` the coefficients the card designed (`kind` `MC_BIQUAD_NONE` and the rest 0: the
 * slot is empty; out of range: `MC_ERR_FILTER_KIND`).
 */
mc_result mc_axis_get_servo_filter(mc_card card,
                                   uint32_t axis,
                                   uint32_t slot,
                                   struct mc_servo_filter *filter);

/**
 * Settings for a path of `ndims` dimensions (1..`MC_PATH_MAX_DIMS`, else `MC_ERR_BAD_AXIS`)
 * with the same limits: look-ahead 256 segments, no low-water event, tangential limits from
 * the dimensions' (0). Nothing is checked until `mc_set_path_open`. Never blocks.
 */
mc_result mc_set_path_settings_uniform(uint32_t ndims,
                                       double vmax,
                                       double amax,
                                       double jmax,
                                       struct mc_set_path_settings *settings);

/**
 * Open a path across the cards `cards[0..ncards]` of one bus (the master first; else
 * `MC_ERR_BAD_CONFIG`): its dimensions are the axes of the groups `parts[0..nparts]` (each a
 * card's index in `cards` and a group of it, configured and enabled, at rest, its path idle),
 * in order, 1 to `MC_PATH_MAX_DIMS` in all. `settings->ndims` must be that count
 * (`MC_ERR_BAD_AXIS`); each limit finite and > 0. A card index outside `cards`, a part named
 * twice, no parts or more than 16: `MC_ERR_BAD_CONFIG`. Every card's group starts the path
 * where the axes are now. Writes the handle to `*path`; close it with `mc_set_path_close`.
 * Blocks until every card has answered.
 */
mc_result mc_set_path_open(const mc_card *cards,
                           size_t ncards,
                           const struct mc_path_part *parts,
                           size_t nparts,
                           const struct mc_set_path_settings *settings,
                           mc_set_path *path);

/**
 * The path's dimensions. Never blocks.
 */
mc_result mc_set_path_dims(mc_set_path path, uint32_t *ndims);

/**
 * Stage a line to `target` (`n` values, one per dimension, user units: `n` must be the
 * path's dimensions, else `MC_ERR_BAD_AXIS`) at `feed`, blended into the segment before
 * within `tolerance` of the corner (0: an exact stop), on every card. A segment the cards
 * refuse is refused by each alike (their code) and staged on none; `MC_ERR_QUEUE_FULL` once
 * 256 are staged: release them first. Blocks until every card has answered.
 */
mc_result mc_set_path_line(mc_set_path path,
                           uint32_t id,
                           const double *target,
                           size_t n,
                           double feed,
                           double tolerance);

/**
 * Stage an arc in `plane` (`MC_ARC_PLANE_`: of two of the first 8 dimensions) described by
 * `*arc` (as `mc_group_move_circular`), a helix when `nhelix` targets of the other dimensions
 * (in order) are given (`helix` may be NULL when `nhelix` is 0: they stay), at `feed`,
 * blended as `mc_set_path_line`. `MC_ERR_BAD_AXIS` for a plane beyond the first 8 dimensions
 * or a helix of another count. Blocks until every card has answered.
 */
mc_result mc_set_path_arc(mc_set_path path,
                          uint32_t id,
                          const struct mc_arc *arc,
                          uint32_t plane,
                          const double *helix,
                          size_t nhelix,
                          double feed,
                          double tolerance);

/**
 * Stage a dwell: an exact stop, then a wait of `seconds`. Blocks until every card has
 * answered.
 */
mc_result mc_set_path_dwell(mc_set_path path, uint32_t id, double seconds);

/**
 * Release everything staged into every card's path on one tick (`*tick`, may be NULL), once
 * every card's path has room for it (`MC_ERR_QUEUE_FULL` after 5 s of card time without
 * room). The first release starts the path; later ones stream the rest while it runs. With
 * nothing staged: the set's tick now. Blocks until the release ran.
 */
mc_result mc_set_path_release(mc_set_path path, uint64_t *tick);

/**
 * Wait until every card's path has run everything released and its group is at rest
 * (`MC_ERR_TIMEOUT` after `timeout_ms`, card time on stepped cards: they are stepped). A group
 * stopped or faulted on one card: the others are halted at once and that is the error
 * (`MC_ERR_INVALID_STATE`). It waits 10 ms at a time: another thread may halt, hold or
 * release the path meanwhile.
 */
mc_result mc_set_path_wait(mc_set_path path, uint32_t timeout_ms);

/**
 * Halt the path on every card on one tick (`*tick`, may be NULL), along its geometry within
 * `deceleration` and `jerk` (> 0, the first dimension's units). What is staged is dropped.
 */
mc_result mc_set_path_halt(mc_set_path path, double deceleration, double jerk, uint64_t *tick);

/**
 * Hold the path on every card on one tick (`*tick`, may be NULL): feed override 0, it comes
 * to rest along its geometry; `mc_set_path_override` above 0 resumes it on every card
 * together.
 */
mc_result mc_set_path_hold(mc_set_path path, uint64_t *tick);

/**
 * Set the feed override of every card's group on one tick (`*tick`, may be NULL).
 */
mc_result mc_set_path_override(mc_set_path path, double factor, uint64_t *tick);

/**
 * Pause the path at the end of a segment on every card on one tick (`on` non-zero), or let it
 * go on (`on` 0); `*tick` (may be NULL): the tick.
 */
mc_result mc_set_path_pause(mc_set_path path, uint32_t on, uint64_t *tick);

/**
 * How far the path has come (each may be NULL): `*staged` segments given and not released,
 * `*queued` released and not finished (on the card that has the most), `*done` finished (on
 * the card that has the fewest). Never blocks (it reads the cards' windows).
 */
mc_result mc_set_path_progress(mc_set_path path,
                               uint32_t *staged,
                               uint32_t *queued,
                               uint32_t *done);

/**
 * Free the path's handle. What runs goes on (halt it first to stop it); the cards stay open.
 * Closing twice: `MC_ERR_BAD_HANDLE`.
 */
mc_result mc_set_path_close(mc_set_path path);

/**
 * MC_GearIn (Aborting): `axis` follows master `master` of kind `master_kind` (`MC_MASTER_`)
 * at `numerator / denominator` encoder counts per master count, computed on the card in
 * integer arithmetic (no drift). The coupling is relative to the engagement point: the slave
 * moves by the ratio times the master's travel from where both were when the card took the
 * command (`mc_gear_get_offset` reads the anchor back as an offset). A commanded master is
 * followed in the same servo tick; an actual one (its encoder, latched at the tick's start)
 * a tick behind, the slave trailing the ratio line by ratio x its velocity x the servo
 * period. It catches up within `limits`;
 * `mc_motion_wait_in_sync` on `*motion` (may be NULL) returns once it is in gear. Refused:
 * `MC_ERR_GEAR_RATIO`, `MC_ERR_SYNC_MASTER` (no such master, the axis itself, a master axis
 * disabled or in ErrorStop), `MC_ERR_INFEASIBLE` (the master runs faster than `limits` let
 * the slave follow), `MC_ERR_NOT_FINITE`, `MC_ERR_NON_POSITIVE_LIMIT`. Blocks until the card
 * answers.
 */
mc_result mc_gear_in(mc_card card,
                     uint32_t axis,
                     uint32_t master_kind,
                     uint32_t master,
                     int64_t numerator,
                     int64_t denominator,
                     const struct mc_sync_limits *limits,
                     struct mc_motion *motion);

/**
 * MC_GearInPos (Aborting): as `mc_gear_in`, and `axis` is at `slave_position` (its user
 * units) exactly when the master is at `master_position` (the master axis's user units, or
 * an auxiliary encoder's counts), velocity and acceleration continuous on the way.
 * `MC_ERR_INFEASIBLE` if that breaks `limits` at the master's present velocity, or if the
 * master is at rest or moving away from the point. `mc_motion_wait_in_sync` returns at the
 * point. Blocks until the card answers.
 */
mc_result mc_gear_in_pos(mc_card card,
                         uint32_t axis,
                         uint32_t master_kind,
                         uint32_t master,
                         int64_t numerator,
                         int64_t denominator,
                         double master_position,
                         double slave_position,
                         const struct mc_sync_limits *limits,
                         struct mc_motion *motion);

/**
 * The engagement offset of `axis`'s gear coupling (`mc_gear_in`, `mc_gear_in_pos`), in
 * counts: in gear the slave's commanded position is `offset + ratio * master` (both in
 * counts; a commanded master's position in counts; the ratio is the coupling's numerator
 * over its denominator). The coupling is relative to the engagement: `mc_gear_in` anchors the
 * ratio line where the slave and the master were when the card took it, `mc_gear_in_pos` at
 * the sync point; the offset is where that line puts the slave with the master at 0.
 * `MC_ERR_INVALID_STATE` when the axis is not geared (or was not geared through this
 * library). Never blocks.
 */
mc_result mc_gear_get_offset(mc_card card, uint32_t axis, double *offset);

/**
 * MC_GearOut: the slave leaves the coupling and keeps moving at its velocity (velocity mode);
 * `mc_motion_wait_in_velocity` on `*motion` (may be NULL) gives the velocity; stop it with
 * `mc_halt`. The gear motion ends `MC_ERR_ABORTED`. `MC_ERR_INVALID_STATE` unless the axis is
 * geared. Blocks until the card answers.
 */
mc_result mc_gear_out(mc_card card, uint32_t axis, struct mc_motion *motion);

/**
 * Wait until a gear motion is in gear (`mc_gear_in`) or in sync (`mc_gear_in_pos`).
 * `position` may be NULL; otherwise it receives the slave's commanded position then (user
 * units). `MC_ERR_ABORTED` if it was aborted first (halt, stop, gear-out, a safety stop, the
 * master lost), `MC_ERR_TIMEOUT` after `timeout_ms`. Blocks.
 */
mc_result mc_motion_wait_in_sync(mc_card card,
                                 struct mc_motion motion,
                                 uint32_t timeout_ms,
                                 double *position);

/**
 * The count of auxiliary encoder `k` as the card published it last tick.
 * `MC_ERR_SYNC_MASTER` for an encoder the card does not have. Never blocks.
 */
mc_result mc_aux_encoder(mc_card card, uint32_t k, int64_t *count);

/**
 * Turn auxiliary encoder `k` of a stepped sim card at `velocity` counts/s (a conveyor, a
 * handwheel). `MC_ERR_UNSUPPORTED` on any other card, `MC_ERR_BAD_CONFIG` for an encoder the
 * card does not have, `MC_ERR_NOT_FINITE`. Never blocks.
 */
mc_result mc_sim_set_aux_velocity(mc_card card, uint32_t k, double velocity);

/**
 * Open `n` (1..16) stepped emulated cards of `axes` axes on one sync bus, the first its
 * master (named `sim0`, `sim1`, …): stepping or waiting on any of them steps all of them,
 * master first. Writes their handles to `cards[0..n]`.
 */
mc_result mc_open_sim_bus(size_t n, uint32_t axes, uint32_t servo_rate_hz, mc_card *cards);

/**
 * The card's name, serial and place on the sync bus.
 */
mc_result mc_get_bus_status(mc_card card, struct mc_bus_status *status);

/**
 * From now until `mc_timed_end`, the commands this thread sends (to any card) are timed to
 * `tick` with commit key `key` (0: none needed): each call returns once its card holds the
 * command (or with its refusal: `MC_ERR_TICK_PASSED`, `MC_ERR_TICK_FAR`, `MC_ERR_TIMED_FULL`,
 * …), and the command runs as the first thing of that tick. `MC_ERR_INVALID_STATE` when
 * this thread times already.
 */
mc_result mc_timed_begin(uint64_t tick, uint32_t key);

/**
 * End `mc_timed_begin`, and wait up to `timeout_ms` for the held commands' answers (they
 * come on their tick): the first refusal (`MC_ERR_NOT_COMMITTED` for a key never committed,
 * `MC_ERR_TIMED_CANCELLED`, or the command's own), `MC_ERR_TIMEOUT`. Without a begin:
 * `MC_ERR_INVALID_STATE`.
 */
mc_result mc_timed_end(uint32_t timeout_ms);

/**
 * Commit `key` for `tick` on `card` (the bus's master, or a card alone): its timed commands
 * run on that tick on it and on every follower. `MC_ERR_NOT_MASTER` on a follower,
 * `MC_ERR_COMMIT_LATE` on or after the tick (nothing of the key runs anywhere).
 */
mc_result mc_sync_commit(mc_card card, uint32_t key, uint64_t tick);

/**
 * Drop the commands `card` holds timed under `key` (0: all); `*dropped` (may be NULL): how
 * many. Each is refused with `MC_ERR_TIMED_CANCELLED`.
 */
mc_result mc_timed_cancel(mc_card card, uint32_t key, uint32_t *dropped);

/**
 * Begin a synchronised start on the cards `cards[0..n]` of one bus (the master first; else
 * `MC_ERR_BAD_CONFIG`): the commands this thread sends until `mc_sync_start` are timed to
 * one tick 20 ms ahead (`*tick`, may be NULL) under a fresh key.
 */
mc_result mc_sync_begin(const mc_card *cards, size_t n, uint64_t *tick);

/**
 * Commit `mc_sync_begin`'s commands on the master and wait until they ran (every card on the
 * same tick, `*tick`, may be NULL). `MC_ERR_COMMIT_LATE`: nothing ran anywhere.
 */
mc_result mc_sync_start(uint64_t *tick);

/**
 * Abandon `mc_sync_begin` (or `mc_timed_begin`): what it sent is cancelled on every card and
 * nothing of it runs.
 */
mc_result mc_sync_abort(void);

/**
 * Halt every moving axis of the cards `cards[0..n]` on one tick (`*tick`, may be NULL).
 */
mc_result mc_sync_halt(const mc_card *cards,
                       size_t n,
                       double deceleration,
                       double jerk,
                       uint64_t *tick);

/**
 * Hold every moving axis of the cards `cards[0..n]` on one tick (override 0).
 */
mc_result mc_sync_hold(const mc_card *cards, size_t n, uint64_t *tick);

/**
 * Set the override of every moving axis of the cards `cards[0..n]` on one tick.
 */
mc_result mc_sync_override(const mc_card *cards, size_t n, double factor, uint64_t *tick);

/**
 * Save what the card holds, read back from the card (never this library's memory), to the
 * TOML file `path` (created or replaced). Loading the file on a card of the same axes and
 * saving it again gives the same bytes. Blocks until the card answers its read-backs.
 */
mc_result mc_config_save(mc_card card, const char *path);

/**
 * Load the TOML configuration file `path`: the whole file is checked first with the card's
 * own rules, and nothing is applied when anything is wrong (`MC_ERR_CONFIG_FILE`;
 * `mc_last_error_message` gives `FILE:LINE: KEY: what is wrong`, e.g.
 * `a.toml:31: axis.0.ffpiv.kp: ...`); then the sections that differ from what the card holds
 * are applied and the card is read back and compared. A section the card refuses after the
 * checks passed (its state changed meanwhile) returns the refusal's code, and the message
 * lists what was applied before it. Blocks until the card answers.
 */
mc_result mc_config_load(mc_card card, const char *path);

/**
 * Compare the TOML configuration file `path` with what the card holds, key by key (the file
 * is checked as by `mc_config_load`; nothing is applied). `*differences` (may be NULL) is the
 * number of keys that differ (0: the card holds what the file says); the text, one
 * `KEY: file VALUE, card VALUE` line per key, is copied into `buf` (`len` bytes, NUL
 * included; `*needed` its size: `MC_ERR_BUFFER_TOO_SMALL` when it does not fit, and then
 * nothing else is written). Blocks until the card answers.
 */
mc_result mc_config_diff(mc_card card,
                         const char *path,
                         uint32_t *differences,
                         char *buf,
                         size_t len,
                         size_t *needed);

/**
 * The axis's servo configuration as the card holds it (read back from the card): servo law,
 * FFPIV gains, DAC limit, in-position windows, jog limits and `scale` (counts per user unit,
 * which the card keeps for hosts). Blocks until the card answers.
 */
mc_result mc_axis_get_settings(mc_card card, uint32_t axis, mc_axis_settings *settings);

/**
 * The axis's PD+ law as the card holds it (read back): `*active` is 1 and `*settings` the
 * gains, drive model and Umax when the axis runs PD+, else `*active` is 0 and `*settings` all
 * zero. Blocks until the card answers.
 */
mc_result mc_axis_get_pdplus(mc_card card,
                             uint32_t axis,
                             mc_pdplus_settings *settings,
                             uint32_t *active);

/**
 * The axis's acc/dec filters as the card holds them (read back). Blocks until the card
 * answers.
 */
mc_result mc_axis_get_filters(mc_card card, uint32_t axis, struct mc_filter_settings *settings);

/**
 * The axis's safety configuration as the card holds it (read back), in user units. Blocks
 * until the card answers.
 */
mc_result mc_axis_get_safety(mc_card card, uint32_t axis, struct mc_safety_settings *settings);

/**
 * The axis's homing configuration as the card holds it (read back). Blocks until the card
 * answers.
 */
mc_result mc_axis_get_homing(mc_card card, uint32_t axis, mc_homing_settings *settings);

/**
 * The digital inputs' configuration as the card holds it (read back). Blocks until the card
 * answers.
 */
mc_result mc_get_io_settings(mc_card card, mc_io_settings *settings);

/**
 * The card-wide safety settings as the card holds them (read back). Blocks until the card
 * answers.
 */
mc_result mc_get_card_safety(mc_card card, mc_card_safety_settings *settings);

/**
 * The servo rate the card runs at (read back), Hz. Blocks until the card answers.
 */
mc_result mc_get_servo_rate(mc_card card, uint32_t *hz);

/**
 * A group's configuration as the card holds it (read back), the tolerance in the first
 * axis's user units: `*configured` is 1 and `*settings` the configuration, or `*configured`
 * is 0 and `*settings` all zero for a group that is not configured. Blocks until the card
 * answers.
 */
mc_result mc_group_get_settings(mc_card card,
                                uint32_t group,
                                struct mc_group_settings *settings,
                                uint32_t *configured);

/**
 * Send one command of the card's register map as it is, for tools and tests that need what
 * the typed calls would refuse: `opcode` one of the `MC_OP_` values (their arguments and
 * flags are the register map's, `firmware-proto/include/mc_dpram.h` in the source), `axis`
 * the axis or group it names, `flags` its flags word, and `nargs` (0..14) arguments from
 * `args` (the rest 0; `args` may be NULL when `nargs` is 0). Blocks until the card answers:
 * `MC_OK` when it accepted the command (`value`, may be NULL, receives its ack's value), or
 * the `MC_ERR_` code of its refusal. The card checks it as any other command. It goes around
 * the library's bookkeeping: a motion started this way has no `mc_motion`, and
 * `MC_OP_HOST_DETACH` with this program's session (`mc_get_safety_status`) ends the session on
 * the card while the handle stays open; the card then halts what moves and refuses motion,
 * power, outputs and configuration (`MC_ERR_NO_SESSION`) until an `MC_OP_HOST_ATTACH` of a
 * session (which arms the watchdog at once). An `opcode` or `axis` above 65535, or more than
 * 14 arguments: `MC_ERR_OUT_OF_RANGE`, nothing sent.
 */
mc_result mc_send_raw(mc_card card,
                      uint32_t opcode,
                      uint32_t axis,
                      uint32_t flags,
                      const double *args,
                      size_t nargs,
                      double *value);


/*
 * The register map's own constants that the comments of this header cite (firmware-proto/include/mc_dpram.h,
 * generated with it): the flags, sizes and codes of raw commands (mc_send_raw) and of the register map's blocks.
 * MC_NACK_ codes are what the card answers a raw command (positive); the library's calls return
 * MC_ERR_ codes.
 */

/**
 * ... and when it goes below again.
 */
#define MC_ANALOG_EV_FALL (1u << 1)

/**
 * `MC_OP_ANALOG_INPUT` flags: `MC_EVENT_ANALOG` when the input goes above.
 */
#define MC_ANALOG_EV_RISE (1u << 0)

#define MC_ANALOG_INPUTS 8u

#define MC_ANALOG_OUTPUTS 4u

/**
 * The ADC's and the DACs' range, +-V.
 */
#define MC_ANALOG_RANGE 10.0

/**
 * `MC_OP_PATH_ARC_NORMAL` (layout 1.13: and `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL`): the end may lie off the plane along the normal (a helix along it).
 */
#define MC_ARC_RISE (1u << 2)

/**
 * A filter's poles lie within 1 - margin of the origin.
 */
#define MC_BIQUAD_POLE_MARGIN 1e-6

/**
 * A raw filter's |b0|, |b1|, |b2| at most this.
 */
#define MC_BIQUAD_RAW_B_MAX 1e6

/**
 * Alone or master: its own clock.
 */
#define MC_BUSST_FREE 0u

/**
 * A follower on the master's ticks.
 */
#define MC_BUSST_LOCKED 1u

/**
 * A follower that lost the master: its own clock, halted.
 */
#define MC_BUSST_LOST 2u

/**
 * On its own clock, no bus.
 */
#define MC_BUS_ALONE 0u

/**
 * Runs on the bus's ticks.
 */
#define MC_BUS_FOLLOWER 2u

/**
 * Drives the bus.
 */
#define MC_BUS_MASTER 1u

/**
 * `MC_OP_CAM_IN` flag (beside the master source).
 */
#define MC_CAM_AT_CYCLE_END (1u << 4)

#define MC_CAM_DATA_MAX 5u

/**
 * Aux = a point on the arc (three-point circle).
 */
#define MC_CIRC_BY_BORDER 2u

/**
 * Aux = centre.
 */
#define MC_CIRC_BY_CENTRE 0u

/**
 * `aux_u` = radius (negative: the arc longer than half a turn).
 */
#define MC_CIRC_BY_RADIUS 1u

/**
 * Else clockwise (ignored for border-point arcs).
 */
#define MC_CIRC_CCW (1u << 4)

/**
 * Helical targets are distances even in an absolute move.
 */
#define MC_CIRC_HELIX_RELATIVE (1u << 7)

/**
 * 2 bits:.
 */
#define MC_CIRC_MODE_SHIFT 2u

/**
 * 2 bits:.
 */
#define MC_CIRC_PLANE_SHIFT 5u

/**
 * `MC_ARC_PLANE_AXES`: 3 bits, the plane's first group axis (u).
 */
#define MC_CIRC_U_SHIFT 22u

/**
 * `MC_ARC_PLANE_AXES`: 3 bits, its second (v): counter-clockwise turns from u towards v; u == v is `MC_NACK_PLANE_AXES`.
 */
#define MC_CIRC_V_SHIFT 25u

/**
 * Fire crossing downwards (single: both bits, either way).
 */
#define MC_CMP_DIR_NEG (1u << 3)

/**
 * Fire crossing upwards.
 */
#define MC_CMP_DIR_POS (1u << 2)

#define MC_CMP_MODE_MASK 3u

#define MC_CMP_MODE_SERIES 1u

#define MC_CMP_MODE_SINGLE 0u

#define MC_CMP_MODE_TABLE 2u

/**
 * Positions per `MC_OP_COMPARE_TABLE` entry.
 */
#define MC_COMPARE_TABLE_MAX 12u

/**
 * The table gives a correction per direction.
 */
#define MC_COMP_BIDIR (1u << 0)

#define MC_COMP_DATA_MAX 4u

#define MC_COMP_MAX_POINTS 256u

/**
 * `axis_config[i]`, `axis_pdplus[i]` and `axis_pidff[i]`.
 */
#define MC_CONFIG_AXIS 2u

/**
 * `axis_filter[i]`.
 */
#define MC_CONFIG_AXIS_FILTER 3u

/**
 * `axis_homing[i]`.
 */
#define MC_CONFIG_AXIS_HOMING 7u

/**
 * `axis_safety[i]`.
 */
#define MC_CONFIG_AXIS_SAFETY 6u

/**
 * `card_config` (index 0).
 */
#define MC_CONFIG_CARD 1u

/**
 * `group_config[i]`.
 */
#define MC_CONFIG_GROUP 4u

/**
 * `group_path[i]`.
 */
#define MC_CONFIG_GROUP_PATH 8u

/**
 * `io_config` (index 0).
 */
#define MC_CONFIG_IO 9u

/**
 * Safety (index 0).
 */
#define MC_CONFIG_SAFETY 5u

/**
 * `io_config.debounce`, ticks.
 */
#define MC_DEBOUNCE_MAX 10000u

/**
 * Ended early: done points measured.
 */
#define MC_FREQ_ABORTED 3u

/**
 * Measured periods per window at most.
 */
#define MC_FREQ_CYCLES_MAX 1000u

/**
 * Every point measured.
 */
#define MC_FREQ_DONE 2u

/**
 * The lowest frequency, Hz.
 */
#define MC_FREQ_MIN_HZ 0.1

/**
 * Mode: the sine on the servo output (volts).
 */
#define MC_FREQ_OUTPUT 1u

/**
 * Points per sweep.
 */
#define MC_FREQ_POINTS_MAX 256u

/**
 * Mode: the sine on the position reference (counts).
 */
#define MC_FREQ_REF 0u

/**
 * `settle_s` at most, s.
 */
#define MC_FREQ_SETTLE_MAX 60.0

#define MC_GANTRY_MAX_SLAVES 4u

/**
 * `MC_EVENT_GROUP_HOMING_FAILED's` code when a halt, stop, disable or safety stop ended it (not one of the `MC_HOMING_ERROR_*`).
 */
#define MC_GROUP_HOME_ABORTED (-1)

#define MC_HANDWHEEL_DETENT_MAX 1024u

#define MC_HANDWHEEL_RATIO_MAX 10000u

#define MC_MAX_GANTRIES 4u

#define MC_MAX_MOVE_TIME 1000000.0

/**
 * The largest period, counts (a position within the turn times 65536 stays exact in a double).
 */
#define MC_MODULO_MAX 1e11

/**
 * The smallest period, counts.
 */
#define MC_MODULO_MIN 1.0

/**
 * Start when the queued moves end (else: a group must be at rest; an axis aborts what it does).
 */
#define MC_MOVE_BUFFERED (1u << 1)

/**
 * The direction of the motion in progress, else of the last one (positive if the axis never moved).
 */
#define MC_MOVE_DIR_CURRENT 3u

/**
 * Negative.
 */
#define MC_MOVE_DIR_NEGATIVE 2u

/**
 * Positive: up to a turn less a count forward.
 */
#define MC_MOVE_DIR_POSITIVE 1u

/**
 * 2 bits of `MC_OP_MOVE_ABSOLUTE's` flags (PLCopen `MC_Direction`):.
 */
#define MC_MOVE_DIR_SHIFT 14u

/**
 * The shorter way round (the default).
 */
#define MC_MOVE_DIR_SHORTEST 0u

#define MC_MOVE_RELATIVE (1u << 0)

/**
 * An analog input or output the card does not have (not a whole number below `MC_ANALOG_INPUTS` / `MC_ANALOG_OUTPUTS`), or a spare DAC the PSO drives.
 */
#define MC_NACK_ANALOG_CHANNEL 145

/**
 * A cut-off below 0 or above half the servo rate (Nyquist).
 */
#define MC_NACK_ANALOG_FILTER 146

/**
 * A threshold beyond `+-MC_ANALOG_RANGE`, a hysteresis below 0 or above 2 `*` `MC_ANALOG_RANGE`, or unknown flags.
 */
#define MC_NACK_ANALOG_THRESHOLD 147

/**
 * A normal-vector arc's plane names a group axis twice (or an axis index that is not a whole number).
 */
#define MC_NACK_ARC_AXES 157

/**
 * A normal-vector arc's normal is zero, or no plane was set (`MC_OP_PATH_ARC_PLANE`) before it.
 */
#define MC_NACK_ARC_NORMAL 156

/**
 * A normal-vector arc's centre, or its end (without `MC_ARC_RISE`), is off the plane through the start by more than the group's tolerance.
 */
#define MC_NACK_ARC_OFF_PLANE 158

/**
 * A piece of `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` alone or out of order: its two entries go together, the move first.
 */
#define MC_NACK_ARC_PIECE 155

/**
 * The card configuration can only change while every axis is disabled.
 */
#define MC_NACK_AXES_ENABLED 10

/**
 * A group axis is moving on its own.
 */
#define MC_NACK_AXIS_BUSY 19

/**
 * A move was commanded on a disabled axis.
 */
#define MC_NACK_AXIS_DISABLED 5

/**
 * Single-axis motion on an axis of an enabled group.
 */
#define MC_NACK_AXIS_GROUPED 20

/**
 * A move, jog, `MC_SetPosition` or `MC_Home` on an axis that is homing.
 */
#define MC_NACK_AXIS_HOMING 65

/**
 * An axis already belongs to another group.
 */
#define MC_NACK_AXIS_IN_OTHER_GROUP 17

/**
 * The move needs an axis the group does not have.
 */
#define MC_NACK_AXIS_NOT_IN_GROUP 18

/**
 * The axis number is not one of this card's axes.
 */
#define MC_NACK_BAD_AXIS 2

/**
 * A stop category other than 0, 1 or 2.
 */
#define MC_NACK_BAD_CATEGORY 38

/**
 * A configuration block holds a value out of its range.
 */
#define MC_NACK_BAD_CONFIG 7

/**
 * No such group.
 */
#define MC_NACK_BAD_GROUP 16

/**
 * Cam data without an open table or out of order.
 */
#define MC_NACK_CAM_SEQUENCE 106

/**
 * A table number, point count or flags out of range, points not strictly increasing in the master or not finite, a table not loaded, or one in use.
 */
#define MC_NACK_CAM_TABLE 105

/**
 * A held timed command dropped (`MC_OP_TIMED_CANCEL`, a detach).
 */
#define MC_NACK_CANCELLED 169

/**
 * Reset refused: the cause (alarm, encoder fault, e-stop input, missing heartbeat) is still present.
 */
#define MC_NACK_CAUSE_ACTIVE 36

/**
 * The centre is not equidistant from start and end within the tolerance.
 */
#define MC_NACK_CENTRE_NOT_EQUIDISTANT 22

/**
 * The three points of a border-point arc are on one line.
 */
#define MC_NACK_COLLINEAR_POINTS 24

/**
 * `MC_OP_SYNC_COMMIT` on or after its tick: nothing of the key runs.
 */
#define MC_NACK_COMMIT_LATE 164

/**
 * The channel is armed (or armed in another mode, or its table has the other direction), or its output is another armed channel's.
 */
#define MC_NACK_COMPARE_BUSY 95

/**
 * The table has no room for the entry's positions.
 */
#define MC_NACK_COMPARE_FULL 93

/**
 * An unknown mode or direction, an output >= `MC_CARD_OUTPUTS`, a pulse width, low-water mark, pitch or count out of its range, or table data of the wrong size.
 */
#define MC_NACK_COMPARE_MODE 92

/**
 * Table positions not strictly monotonic in the direction.
 */
#define MC_NACK_COMPARE_ORDER 94

/**
 * Layout 1.13, compare on a modulo axis: a position, series start or table position outside 0 <= p < modulo, a series longer than a turn ((count - 1) `*` pitch >= modulo; with `MC_CMP_EACH_TURN` count `*` pitch > modulo, or count 0 with a pitch over the turn), `MC_CMP_EACH_TURN` on a linear axis, or `MC_OP_SET_MODULO` on an axis an armed compare channel watches. Refused, nothing changed.
 */
#define MC_NACK_COMPARE_TURN 159

/**
 * A correction beyond the table's bound.
 */
#define MC_NACK_COMP_BOUND 123

/**
 * The axis is not at rest: its compensation cannot change.
 */
#define MC_NACK_COMP_BUSY 124

/**
 * Compensation positions not strictly increasing.
 */
#define MC_NACK_COMP_ORDER 122

/**
 * Compensation data without an open table, or out of order.
 */
#define MC_NACK_COMP_SEQUENCE 121

/**
 * Compensation: a point count, bound, backlash, ramp or flags out of range.
 */
#define MC_NACK_COMP_TABLE 120

/**
 * `MC_OP_READ_CONFIG`: an unknown block kind, or a kind or index that is not an integer.
 */
#define MC_NACK_CONFIG_KIND 116

/**
 * An e-stop is latched: `MC_OP_SAFETY_RESET` first.
 */
#define MC_NACK_ESTOP_ACTIVE 33

/**
 * Served after its deadline (the command's `deadline_ms`): not executed.
 */
#define MC_NACK_EXPIRED 13

/**
 * Filters can change only while they hold no distance.
 */
#define MC_NACK_FILTER_BUSY 28

/**
 * A filter frequency not above 0 and below the Nyquist frequency (`servo_rate_hz` / 2).
 */
#define MC_NACK_FILTER_FREQ 141

/**
 * A filter slot or kind out of range or not an integer.
 */
#define MC_NACK_FILTER_KIND 140

/**
 * A filter's damping (0 < damping <= 10), depth (-120 <= `depth_db` <= 0) or raw b (|b| <= `MC_BIQUAD_RAW_B_MAX`) out of range.
 */
#define MC_NACK_FILTER_PARAM 142

/**
 * The filter's poles are not inside the unit circle by `MC_BIQUAD_POLE_MARGIN`.
 */
#define MC_NACK_FILTER_UNSTABLE 143

/**
 * A sweep's amplitude not above 0, or above the axis's DAC limit for `MC_FREQ_OUTPUT`.
 */
#define MC_NACK_FREQ_AMPLITUDE 151

/**
 * A sweep is running: another, or that axis's motion, refused.
 */
#define MC_NACK_FREQ_BUSY 153

/**
 * The sweep's sine would break the axis's velocity or acceleration limits, its following error limit at rest or its soft limits.
 */
#define MC_NACK_FREQ_LIMITS 152

/**
 * A sweep's mode, points, cycles, settle time or frequencies out of range (`from_hz` below `MC_FREQ_MIN_HZ` or above `to_hz`, `to_hz` above a quarter of the servo rate).
 */
#define MC_NACK_FREQ_RANGE 150

/**
 * Gantry index, master or slaves out of range, master == slave, a slave twice.
 */
#define MC_NACK_GANTRY_AXES 136

/**
 * Kp, ki, skew limit or square offset out of range.
 */
#define MC_NACK_GANTRY_GAINS 137

/**
 * A gantry member already in a gantry, a group, geared or streaming.
 */
#define MC_NACK_GANTRY_IN_USE 135

/**
 * The axis is a slave of a formed gantry: it cannot be used by itself.
 */
#define MC_NACK_GANTRY_SLAVE 134

/**
 * The gantry (or its members) not in a state that takes this.
 */
#define MC_NACK_GANTRY_STATE 138

/**
 * A ratio that is not integer, a zero numerator, a denominator <= 0, or a magnitude above `MC_GEAR_RATIO_MAX`.
 */
#define MC_NACK_GEAR_RATIO 100

/**
 * A move on a disabled group.
 */
#define MC_NACK_GROUP_DISABLED 27

/**
 * A handwheel input the card does not have (not a whole number in `0..MC_AUX_ENCODERS-1`).
 */
#define MC_NACK_HANDWHEEL_INPUT 129

/**
 * A handwheel ratio that is 0, not a whole number or beyond `MC_HANDWHEEL_RATIO_MAX`, or a detent outside `1..MC_HANDWHEEL_DETENT_MAX`.
 */
#define MC_NACK_HANDWHEEL_RATIO 130

/**
 * The move goes further into an active limit switch.
 */
#define MC_NACK_HARD_LIMIT 34

/**
 * A home order names an axis the group does not have.
 */
#define MC_NACK_HOME_AXIS 131

/**
 * A home order with an empty stage (or no stages, and none configured).
 */
#define MC_NACK_HOME_STAGE 133

/**
 * A home order names an axis in two stages.
 */
#define MC_NACK_HOME_TWICE 132

/**
 * A homing method the axis cannot do: an unknown number, or an index method without `MC_HOMING_FLAG_INDEX`.
 */
#define MC_NACK_HOMING_METHOD 64

/**
 * The interpolator cannot run with the group's acc/dec mode.
 */
#define MC_NACK_INCOMPATIBLE_MODE 26

/**
 * No profile satisfies the request.
 */
#define MC_NACK_INFEASIBLE 8

/**
 * The command is not allowed in the axis's current state.
 */
#define MC_NACK_INVALID_STATE 6

/**
 * A compare or probe channel that is not an integer in `0..MC_COMPARE_CHANNELS-1` (`MC_PROBE_CHANNELS-1`).
 */
#define MC_NACK_IO_CHANNEL 91

/**
 * `io_config`: a mask bit beyond `MC_CARD_INPUTS` or a debounce over `MC_DEBOUNCE_MAX`.
 */
#define MC_NACK_IO_CONFIG 90

/**
 * A kinematic limit outside its range (see `MC_MAX_MOVE_TIME`).
 */
#define MC_NACK_LIMIT_RANGE 11

/**
 * The axis is not at rest: its period cannot change.
 */
#define MC_NACK_MODULO_BUSY 126

/**
 * An absolute move that does not fit the axis: on a modulo axis a target not in 0 <= target < modulo, on a linear axis a direction other than `MC_MOVE_DIR_SHORTEST`.
 */
#define MC_NACK_MODULO_MOVE 127

/**
 * A modulo period below `MC_MODULO_MIN` or above `MC_MODULO_MAX`, or negative.
 */
#define MC_NACK_MODULO_RANGE 125

/**
 * A velocity, acceleration or jerk limit is zero or negative.
 */
#define MC_NACK_NON_POSITIVE_LIMIT 4

/**
 * A timed command whose key's commit was not seen by its tick.
 */
#define MC_NACK_NOT_COMMITTED 166

/**
 * An argument is NaN or infinite.
 */
#define MC_NACK_NOT_FINITE 3

/**
 * `MC_OP_SYNC_COMMIT` on a follower: commit on the bus's master.
 */
#define MC_NACK_NOT_MASTER 165

/**
 * A command the session gate refuses (see `MC_OP_HOST_ATTACH`): no session attached with its watchdog armed.
 */
#define MC_NACK_NO_SESSION 41

/**
 * Fewer than degree+1 or more than 1024 control points.
 */
#define MC_NACK_NURBS_CTRL_COUNT 51

/**
 * Degree outside 1..5.
 */
#define MC_NACK_NURBS_DEGREE 49

/**
 * The group has fewer than 2 axes.
 */
#define MC_NACK_NURBS_DIMENSION 50

/**
 * A knot not finite (NaN or infinite).
 */
#define MC_NACK_NURBS_KNOT 60

/**
 * Knots decrease.
 */
#define MC_NACK_NURBS_KNOTS_DECREASING 53

/**
 * `n_knots` != `n_ctrl` + degree + 1.
 */
#define MC_NACK_NURBS_KNOT_COUNT 52

/**
 * An interior knot repeated more than degree times.
 */
#define MC_NACK_NURBS_KNOT_MULTIPLICITY 54

/**
 * End knots not repeated degree+1 times, or an empty domain.
 */
#define MC_NACK_NURBS_NOT_CLAMPED 55

/**
 * A control point not finite.
 */
#define MC_NACK_NURBS_POINT 57

/**
 * DATA/END without BEGIN, data out of order or missing.
 */
#define MC_NACK_NURBS_SEQUENCE 48

/**
 * The curve does not start where the group's path is.
 */
#define MC_NACK_NURBS_START 58

/**
 * A weight not finite and > 0.
 */
#define MC_NACK_NURBS_WEIGHT 56

/**
 * The curve has zero length.
 */
#define MC_NACK_NURBS_ZERO_LENGTH 59

/**
 * A position or distance is beyond the card's range.
 */
#define MC_NACK_OUT_OF_RANGE 9

/**
 * An override factor outside `0..MC_OVERRIDE_MAX`.
 */
#define MC_NACK_OVERRIDE_RANGE 14

/**
 * A path segment while group moves run, a group move while the path runs, or `group_path` applied while it runs.
 */
#define MC_NACK_PATH_BUSY 83

/**
 * A NURBS path segment with a point of zero tangent, or needing more pieces than the path buffer holds.
 */
#define MC_NACK_PATH_CURVE 85

/**
 * `group_dims`: ndims over `MC_PATH_MAX_DIMS`, an `axis[]` that is not a group axis or `MC_DIM_REMOTE`, a group axis named twice or not at all, a group not configured; or a staging command on a group without dimensions (`MC_OP_PATH_MORE`, `MC_OP_PATH_RELEASE`).
 */
#define MC_NACK_PATH_DIMS 170

/**
 * A segment id that is not an integer in 0..2^32-1.
 */
#define MC_NACK_PATH_ID 84

/**
 * A buffer or transition mode the card does not know, or a time-shifted transition it cannot make (`MC_PATH_TRANSITION_TIME_SHIFT`).
 */
#define MC_NACK_PATH_MODE 80

/**
 * A segment of more dimensions than its entry holds without its `MC_OP_PATH_MORE` right after it, or an `MC_OP_PATH_MORE` alone.
 */
#define MC_NACK_PATH_MORE 171

/**
 * An output number >= `MC_CARD_OUTPUTS`, a value other than 0/1, or more than `MC_PATH_OUTPUTS_PENDING` actions pending.
 */
#define MC_NACK_PATH_OUTPUT 82

/**
 * `MC_OP_PATH_RELEASE` of more segments than are staged (or 0), or with the group moved off where the staged segments start.
 */
#define MC_NACK_PATH_RELEASE 172

/**
 * A line of length zero.
 */
#define MC_NACK_PATH_ZERO_LENGTH 81

/**
 * `MC_OP_APPLY_AXIS_CONFIG` with `MC_SERVO_PIDFF`: a gain negative, a derivative cut-off or a friction deadband not above 0 (not finite: `MC_NACK_NOT_FINITE`).
 */
#define MC_NACK_PIDFF_GAINS 144

/**
 * An arc's plane of two group axes names one axis twice.
 */
#define MC_NACK_PLANE_AXES 139

/**
 * The planned profile failed the card's own check (shorter than |d|/vmax, off its target or beyond a limit): refused, not run.
 */
#define MC_NACK_PLAN_CHECK 12

/**
 * A probe input beyond `MC_PROBE_INPUT_INDEX`, no edge or an unknown flag, or a window with `window_lo` > `window_hi`.
 */
#define MC_NACK_PROBE_INPUT 96

/**
 * A PSO output, gate, range (min > max, beyond the DAC's range or a duty beyond 0..1), `v_ref` (<= 0), PWM frequency or filter (below 0, above half the servo rate) out of range, the gate equal to the PWM output, a PWM output a compare channel pulses, or unknown flags.
 */
#define MC_NACK_PSO_CONFIG 148

/**
 * A PSO on a group that does not exist (index beyond `MC_GROUP_COUNT`) or is not configured.
 */
#define MC_NACK_PSO_GROUP 149

/**
 * `MC_OP_COMPARE_ARM` on the digital output the PSO's PWM holds (layout 1.12): refused, nothing changed (the other way, a PSO's PWM on an output a compare channel pulses, is `MC_NACK_PSO_CONFIG`).
 */
#define MC_NACK_PSO_OUTPUT 154

/**
 * A point whose segment breaks the stream's vmax or amax, or a last point (PVT) with a velocity.
 */
#define MC_NACK_PVT_LIMIT 103

/**
 * Points without an open stream or after its last point, a start without points or on an axis that moved, a begin while one runs.
 */
#define MC_NACK_PVT_SEQUENCE 104

/**
 * A point not at least one servo period after the one before, or a segment longer than `MC_MAX_MOVE_TIME`.
 */
#define MC_NACK_PVT_TIME 102

/**
 * The group's (or the axis's) move queue is full.
 */
#define MC_NACK_QUEUE_FULL 25

/**
 * The radius is shorter than half the chord.
 */
#define MC_NACK_RADIUS_TOO_SMALL 23

/**
 * `n_channels` 0 or above `MC_SCOPE_CHANNELS`.
 */
#define MC_NACK_SCOPE_CHANNELS 111

/**
 * A divider 0 or above `MC_SCOPE_DIVIDER_MAX`.
 */
#define MC_NACK_SCOPE_DIVIDER 112

/**
 * `pre_trigger` above `MC_SCOPE_PRETRIGGER_MAX`.
 */
#define MC_NACK_SCOPE_PRETRIGGER 114

/**
 * An unknown signal, or an axis or group index the card has not.
 */
#define MC_NACK_SCOPE_SIGNAL 110

/**
 * Configure or arm while armed, trigger while not waiting, stop while idle, arm before a configure.
 */
#define MC_NACK_SCOPE_STATE 115

/**
 * An unknown mode, trigger kind or edge, a trigger channel >= `n_channels`, a trigger input >= `MC_CARD_INPUTS`, a level not finite, or a one-shot with `post_trigger` 0.
 */
#define MC_NACK_SCOPE_TRIGGER 113

/**
 * A detach by a host whose session is not the attached one.
 */
#define MC_NACK_SESSION 40

/**
 * The move goes further beyond a soft limit.
 */
#define MC_NACK_SOFT_LIMIT 35

/**
 * A stop ramp from `max_velocity` longer than the maximum stop time, or a maximum stop time out of range.
 */
#define MC_NACK_STOP_TOO_LONG 39

/**
 * A timed command dropped: the card lost the bus's master.
 */
#define MC_NACK_SYNC_LOST 167

/**
 * A master source the card does not know, a master axis or aux encoder it does not have, the slave itself, or a master axis disabled or in ErrorStop.
 */
#define MC_NACK_SYNC_MASTER 101

/**
 * A tick more than `MC_TIMED_MAX_AHEAD` ticks ahead, or a key or tick that is not a whole number in range.
 */
#define MC_NACK_TICK_FAR 163

/**
 * `MC_OP_AT_TICK` for a tick the card has run (layout 1.12).
 */
#define MC_NACK_TICK_PASSED 160

/**
 * `MC_OP_AT_TICK` without a command published with it, or timing a command that cannot be timed (`MC_OP_AT_TICK`, the session and commit opcodes, the pieces of `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL`).
 */
#define MC_NACK_TIMED_ALONE 162

/**
 * `MC_TIMED_SLOTS` timed commands are held already.
 */
#define MC_NACK_TIMED_FULL 161

/**
 * The command of a refused `MC_OP_AT_TICK`: not executed.
 */
#define MC_NACK_TIMED_REFUSED 168

/**
 * The opcode is not defined by this firmware.
 */
#define MC_NACK_UNKNOWN_OPCODE 1

/**
 * Watchdog timeout 0 or under 1.5 x `host.host_period_us`.
 */
#define MC_NACK_WATCHDOG_TIMEOUT 37

/**
 * The host watchdog fault is latched: `MC_OP_SAFETY_RESET` first.
 */
#define MC_NACK_WATCHDOG_TRIPPED 32

/**
 * The arc has zero length (or zero radius).
 */
#define MC_NACK_ZERO_LENGTH_ARC 21

/**
 * Saturation-aware feed (Yeh 3.4): needs PD+ axes.
 */
#define MC_NURBS_SATURATION (1u << 2)

/**
 * 200 %.
 */
#define MC_OVERRIDE_MAX 2.0

/**
 * The last segment of a program: its stop is not starvation.
 */
#define MC_PATH_LAST (1u << 21)

/**
 * Dimensions of a path across cards.
 */
#define MC_PATH_MAX_DIMS 16u

#define MC_PATH_OUTPUTS_PENDING 8u

#define MC_PROBE_CONTINUOUS (1u << 2)

/**
 * A capture halts the axis's group or the axis (layout 1.9).
 */
#define MC_PROBE_HALT (1u << 4)

#define MC_PROBE_WINDOW (1u << 3)

/**
 * `cmd_head` - `cmd_tail` > `MC_CMD_RING_LEN`.
 */
#define MC_PROTO_CMD_RING 1

/**
 * `evt_head` - `evt_tail` > `MC_EVT_RING_LEN`.
 */
#define MC_PROTO_EVT_RING 2

/**
 * `MC_OP_PSO` flags: a PWM on a digital output (else a spare DAC).
 */
#define MC_PSO_PWM (1u << 0)

/**
 * The highest PWM frequency, Hz.
 */
#define MC_PSO_PWM_HZ_MAX 100000.0

/**
 * `MC_OP_GROUP_MOVE_PTP`: every axis's limits were staged (else `MC_NACK_BAD_CONFIG`).
 */
#define MC_PTP_AXIS_LIMITS (1u << 10)

#define MC_PVT_LAST (1u << 1)

/**
 * Points per `MC_OP_PVT_POINTS`.
 */
#define MC_PVT_POINTS_MAX 4u

#define MC_PVT_PT (1u << 0)

/**
 * Encoder to a kilometre on a fine one.
 */
#define MC_SCALE_MAX 1e12

/**
 * |counts per user unit|: a nanometre-class unit on a coarse.
 */
#define MC_SCALE_MIN 1e-9

/**
 * `scope_config.divider`: `1..MC_SCOPE_DIVIDER_MAX`.
 */
#define MC_SCOPE_DIVIDER_MAX 65536u

/**
 * `scope_config.pre_trigger`: `0..MC_SCOPE_PRETRIGGER_MAX`.
 */
#define MC_SCOPE_PRETRIGGER_MAX 1024u

#define MC_SCOPE_SOURCE(signal, index) ((uint32_t)(signal) | ((uint32_t)(index) << 16))

#define MC_STATUS_WORDS 25u

/**
 * The farthest a timed command may look ahead, ticks.
 */
#define MC_TIMED_MAX_AHEAD 600000u

#define MC_CMD_RING_LEN 64u

/**
 * Layout 1.13, a modulo axis only (else `MC_NACK_COMPARE_TURN`): a single position or a series fires on every turn, endless (see above).
 */
#define MC_CMP_EACH_TURN (1u << 4)

/**
 * `group_dims.axis[]`: a dimension another card drives.
 */
#define MC_DIM_REMOTE (-1)

#define MC_EVT_RING_LEN 256u

/**
 * |numerator|, denominator <= 2^31 - 1.
 */
#define MC_GEAR_RATIO_MAX 2147483647.0

/**
 * Timed commands a card holds at once.
 */
#define MC_TIMED_SLOTS 16u
#ifdef __cplusplus
}  /* extern "C" */
#endif

#endif  /* MOTIONCARD_H */
