/*
 * mc_dpram.h - the DPRAM register map of the motion card.
 *
 * This header is the single source of truth for the host <-> card contract. The Rust bindings in
 * firmware-proto/src/raw.rs are generated from it (`cargo xtask codegen`) and checked in.
 *
 * Conventions
 * - All multi-byte fields are little-endian, naturally aligned. Floating point is IEEE-754 binary64.
 * - Every field has exactly one writer: "host" or "card" in the comment before each block.
 * - Units: positions in encoder counts, time in seconds, velocity counts/s, acceleration
 *   counts/s^2, jerk counts/s^3, DAC output in volts.
 * - Rings are single-producer single-consumer with free-running u32 indices; the entry for index
 *   i is entries[i & (LEN - 1)]. The producer writes the entry, then publishes its index with a
 *   release store; the consumer loads the peer index with acquire. head - tail <= LEN always.
 * - Status blocks are seqlocks: the card makes `seq` odd, writes the payload, makes it even.
 */
#ifndef MC_DPRAM_H
#define MC_DPRAM_H

#include <stdint.h>

#define MC_MAGIC 0x5044434Du /* "MCDP" read as little-endian bytes */
#define MC_LAYOUT_MAJOR 1u
#define MC_LAYOUT_MINOR 14u /* 1: groups, filters, NURBS, PD+ and the safety blocks appended; 2: group status
                           * snap_last/snap_max, MC_OP_GROUP_PTP_LIMITS, MC_NACK_NURBS_KNOT; 3: host sessions
                           * (MC_OP_HOST_ATTACH/DETACH), command deadlines (host_time_ms, deadline_ms), the
                           * maximum stop time, kinematic limit ranges, heartbeat lateness; 4: loss counters
                           * in the card control block (card.bad_accesses, outbox_lost,
                           * safety_events_lost); 5: moves from any state (buffer modes, MC_OP_MOVE_ADDITIVE),
                           * velocity mode and jog, override, axis motion flags and queue in the status;
                           * homing: MC_OP_APPLY_AXIS_HOMING with the axis_homing[] blocks (appended),
                           * MC_OP_HOME (the CiA 402 methods), MC_OP_SET_POSITION, MC_EV_HOMING_FAILED
                           * and its MC_HOMING_ERR_* codes, MC_STOP_HOMING_FAILED,
                           * MC_NACK_HOMING_METHOD, MC_NACK_AXIS_HOMING; soft limits hold once the axis
                           * is homed (MC_MOTION_HOMED); 6: the continuous path (MC_OP_PATH_*, the group_path[] blocks
                           * appended, path words in the group status, MC_EV_SEGMENT_*,
                           * MC_EV_PATH_*, MC_NACK_PATH_*), the card's digital outputs
                           * (card.outputs, MC_OP_SET_OUTPUTS); 7: digital inputs (card.inputs,
                           * card.inputs_raw, the io_config block: polarity, debounce, MC_EV_INPUT
                           * edges), position compare (MC_OP_COMPARE_*, compare_status[],
                           * MC_EV_COMPARE), touch probes (MC_OP_PROBE_*, probe_status[],
                           * MC_EV_PROBE), MC_NACK_IO_* / _COMPARE_* / _PROBE_* (opcodes 64..69,
                           * nacks 90..96, events 24..26; blocks appended), NURBS curves in the path
                           * (MC_OP_PATH_NURBS, MC_NACK_PATH_CURVE); synchronised motion: gearing,
                           * PT/PVT streams, camming (opcodes 80..89, nacks 100..106, MC_EV_SYNC,
                           * MC_EV_PVT, MC_MOTION_IN_SYNC, the sync_status block appended);
                           * 8: the scope (MC_OP_SCOPE_*, opcodes 90..93, MC_NACK_SCOPE_* 110..115,
                           * MC_EV_SCOPE 29; scope_config, scope_status, the scope ring's indices
                           * and the scope ring appended; MC_DPRAM_SIZE 32 KiB -> 1 MiB);
                           * MC_CAM_RELATIVE (MC_CamIn's StartMode relative); the configuration
                           * read back (MC_OP_READ_CONFIG 96, MC_CONFIG_*, MC_NACK_CONFIG_KIND 116),
                           * each axis's scale on the card (mc_axis_config.scale, MC_OP_SET_SCALE
                           * 97), the path planner's period (mc_group_path.plan_period, from
                           * its reserved words; 0 keeps the default); the session gate
                           * (MC_NACK_NO_SESSION 41, MC_STOP_NO_SESSION 33; an attach arms the
                           * watchdog); 9: leadscrew compensation (MC_OP_COMP_* 98..100,
                           * MC_NACK_COMP_* 120..124, comp_readback appended), the status
                           * payloads grew to 25 words (axis: comp_pos; group: a reserved word),
                           * their checksum is word 24; a touch probe that halts its axis's
                           * motion on the capture (MC_PROBE_HALT, MC_STOP_PROBE 7);
                           * 10: arcs in the plane of any two group axes (MC_PLANE_AXES,
                           * MC_CIRC_U_SHIFT, MC_CIRC_V_SHIFT, MC_NACK_PLANE_AXES 139); the
                           * handwheel (MC_OP_HANDWHEEL 104, MC_OP_HANDWHEEL_OFF 105,
                           * MC_NACK_HANDWHEEL_INPUT 129, MC_NACK_HANDWHEEL_RATIO 130); gantry
                           * axes (MC_OP_GANTRY_* 108..110, MC_NACK_GANTRY_* 134..138,
                           * MC_EV_GANTRY_FAULT 32, MC_EV_GANTRY_HOMED 33, MC_STOP_GANTRY_SKEW 34,
                           * MC_STOP_GANTRY 35, MC_SIG_GANTRY_SKEW 14, gantry_status[] appended);
                           * the scope's MC_SIG_COMP_POS 15;
                           * rotary (modulo) axes (MC_OP_SET_MODULO 101,
                           * mc_axis_config.modulo from its reserved word, the direction of
                           * MC_OP_MOVE_ABSOLUTE in its flags: MC_MOVE_DIR_*, MC_NACK_MODULO_*
                           * 125..127); the status's positions wrap into [0, modulo);
                           * 11: a pause at the end of a path segment (MC_OP_PATH_PAUSE 120,
                           * MC_PATHST_PAUSING, MC_PATHST_PAUSED, MC_EV_PATH_PAUSED 36); group
                           * homing (MC_OP_GROUP_HOME 106, mc_group_config.home_stages
                           * and home_order[] from its reserved words, MC_NACK_HOME_* 131..133,
                           * MC_EV_GROUP_HOMED 30, MC_EV_GROUP_HOMING_FAILED 31,
                           * MC_STOP_GROUP_HOMING 8; the group enters MC_GROUP_HOMING);
                           * the PID + feed-forward servo law (MC_SERVO_PIDFF 2, the
                           * axis_pidff[] blocks appended), biquad filters on the servo output
                           * (MC_OP_SERVO_FILTER_SET 112, MC_OP_SERVO_FILTER_CLEAR 113,
                           * MC_BIQUAD_*, MC_NACK_FILTER_* 140..143, MC_NACK_PIDFF_GAINS 144,
                           * servo_filters[] appended), MC_SIG_FILTER_IN 16, MC_SIG_FILTER_OUT 17,
                           * MC_SIG_SERVO_FRICTION 18; analog I/O and the path-speed output (MC_OP_ANALOG_INPUT 116,
                           * MC_OP_ANALOG_OUTPUT 117, MC_OP_PSO 118, MC_OP_PSO_OFF 119,
                           * MC_NACK_ANALOG_* 145..147, MC_NACK_PSO_* 148..149,
                           * MC_EV_ANALOG 34, MC_SIG_AIN0..7 51..58, MC_SIG_AOUT0..3 59..62,
                           * MC_SIG_PSO 63, analog_status appended);
                           * 12: the sync bus and timed commands (MC_OP_AT_TICK 126,
                           * MC_OP_SYNC_COMMIT 127, MC_OP_TIMED_CANCEL 128, MC_NACK_* 160..169,
                           * MC_EV_SYNC_BUS 38, MC_EV_TIMED 39, MC_STOP_SYNC_LOST 9, card_info
                           * appended: the card's name, serial and sync role); path arcs in a
                           * plane given by a normal vector (MC_OP_PATH_ARC_PLANE
                           * 124, MC_OP_PATH_ARC_NORMAL 125, MC_ARC_RISE, MC_NACK_ARC_NORMAL 156,
                           * MC_NACK_ARC_AXES 157, MC_NACK_ARC_OFF_PLANE 158); the frequency
                           * response measured on the card (MC_OP_FREQ_START
                           * 121, MC_OP_FREQ_STOP 122, MC_FREQ_*, MC_NACK_FREQ_* 150..153,
                           * MC_EV_FREQ_DONE 37, MC_SIG_FREQ_INJECT 19, MC_SIG_FREQ_HZ 20,
                           * freq_status appended); MC_NACK_PSO_OUTPUT 154 (a compare channel
                           * armed on the output the PSO's PWM holds);
                           * 13: position compare on modulo (rotary) axes is turn-aware: its
                           * positions are in [0, modulo) and fire at every crossing, on any
                           * turn and across the wrap; MC_CMP_EACH_TURN (1u << 4, a single
                           * position or a series repeated on every turn; a series' count 0:
                           * a whole turn of pitches), MC_NACK_COMPARE_TURN 159;
                           * MC_MoveCircular in a plane given by a normal vector in the
                           * group's move queue (MC_OP_GROUP_MOVE_CIRCULAR_NORMAL 129 and its
                           * second entry MC_OP_GROUP_CIRCULAR_PLANE 131, published together;
                           * MC_NACK_ARC_PIECE 155; no block);
                           * 14: paths across cards: a group's path dimensions (group_dims[]
                           * appended, MC_OP_APPLY_GROUP_DIMS 132: up to MC_PATH_MAX_DIMS path
                           * axes, each a group axis or one another card drives), segments
                           * staged and released on a tick (MC_OP_PATH_MORE 133,
                           * MC_OP_PATH_RELEASE 134), path_staged in the group status,
                           * MC_NACK_PATH_DIMS 170, MC_NACK_PATH_MORE 171,
                           * MC_NACK_PATH_RELEASE 172) */

#define MC_MAX_AXES 8u
#define MC_MAX_GROUPS 4u
#define MC_GROUP_QUEUE_LEN 32u /* buffered group moves per group */
#define MC_CMD_RING_LEN 64u
#define MC_EVT_RING_LEN 256u
#define MC_CMD_ARGS 14u
#define MC_STATUS_WORDS 25u
#define MC_STATUS_CHECK 0xA5A5A5A5A5A5A5A5ull

#define MC_SERVO_RATE_MIN_HZ 1000u
#define MC_SERVO_RATE_MAX_HZ 20000u

/* What the card accepts; anything outside is refused with its own nack, never clamped.
 * - Positions: |p| <= MC_MAX_POSITION counts (2^52: binary64 still resolves one count there).
 * - Moves: at most MC_MAX_MOVE_TIME seconds long (else MC_NACK_INFEASIBLE).
 * - Kinematic limits (moves, halts and stops, group and NURBS feeds, safety stop ramps): a limit
 *   of order k (k = 1 velocity, 2 acceleration, 3 jerk; counts and seconds) lies in
 *   [MC_MAX_MOVE_TIME^-k, MC_MAX_POSITION * servo_rate_hz^k], from one count in the longest
 *   move to the whole position range in one servo tick (else MC_NACK_LIMIT_RANGE). Subnormal
 *   and absurd values are outside by construction. */
#define MC_MAX_POSITION 4503599627370496.0
#define MC_MAX_MOVE_TIME 1000000.0

/* identity.capabilities bits */
#define MC_CAP_SCURVE (1u << 0)    /* S-curve profiles */
#define MC_CAP_FFPIV (1u << 1)     /* the FFPIV servo loop */
#define MC_CAP_EVENT_IRQ (1u << 2) /* events raise an interrupt */

/* identity.card_state */
#define MC_CARD_BOOTING 0u
#define MC_CARD_RUNNING 1u
#define MC_CARD_HALTED 2u

/* Command opcodes (mc_cmd.opcode). Every command is answered by exactly one ACK or NACK event
 * carrying its seq. */
#define MC_OP_NOP 1u               /* does nothing but answer: the round-trip probe */
#define MC_OP_POWER_ON 2u          /* MC_Power Enable=TRUE */
#define MC_OP_POWER_OFF 3u         /* MC_Power Enable=FALSE */
#define MC_OP_MOVE_ABSOLUTE 4u     /* args: target, vmax, amax, dmax, j1, j3, j5, j7. flags: MC_MOVE_BUFFERED,
                                    * a direction (layout 1.10: MC_MOVE_DIR_*, modulo axes only) */
#define MC_OP_MOVE_RELATIVE 5u     /* args: distance (from the commanded position), then as MOVE_ABSOLUTE */
#define MC_OP_HALT 6u              /* args: dmax, jerk. Decelerate, then Standstill */
#define MC_OP_STOP 7u              /* args: dmax, jerk. Decelerate, stay in Stopping */
#define MC_OP_STOP_RELEASE 8u      /* leave Stopping once at rest (MC_Stop Execute=FALSE) */
#define MC_OP_RESET 9u             /* MC_Reset: ErrorStop -> Standstill or Disabled */
#define MC_OP_APPLY_AXIS_CONFIG 10u /* copy and validate axis_config[axis] */
#define MC_OP_APPLY_CARD_CONFIG 11u /* copy and validate card_config (axis field ignored) */
/* Layout 1.5: single-axis moves from any state. Without MC_MOVE_BUFFERED a move is PLCopen
 * Aborting: it takes over in the tick it is served, from the commanded position, velocity and
 * acceleration (no jump in any of them), and the motion it replaces (and every buffered move) is
 * aborted. With MC_MOVE_BUFFERED it waits in the axis's queue (MC_AXIS_QUEUE_LEN moves, else
 * MC_NACK_QUEUE_FULL) until the motion before it is done (in position, or at its velocity);
 * MC_EV_MOTION_ACTIVE tells when it starts. A move that starts while the axis moves is planned
 * with one jerk, the smallest of j1, j3, j5, j7 (time-optimal from any state). */
#define MC_OP_MOVE_ADDITIVE 12u    /* args: distance (from the target of the last move), then as MOVE_ABSOLUTE */
#define MC_OP_MOVE_VELOCITY 13u    /* MC_MoveVelocity: args: velocity (signed), amax, dmax, jerk.
                                    * ContinuousMotion; MC_EV_IN_VELOCITY once at the velocity. Aborting */
#define MC_OP_JOG 14u              /* velocity mode with the jog feed: args: velocity (signed, |v| <=
                                    * axis_config.jog_max_vel, else MC_NACK_OUT_OF_RANGE) at the axis's
                                    * jog_accel and jog_jerk. Releasing the button is MC_OP_HALT */
#define MC_OP_SET_OVERRIDE 15u     /* MC_SetOverride: args: velocity factor 0..MC_OVERRIDE_MAX (else
                                    * MC_NACK_OVERRIDE_RANGE). Scales the axis's velocity limit (moves)
                                    * or velocity (velocity mode); the change is planned from the current
                                    * state within the acceleration and jerk limits. 0 holds the axis
                                    * still in its motion state; a factor > 0 resumes from there */
#define MC_AXIS_QUEUE_LEN 16u      /* buffered single-axis moves per axis */
#define MC_OVERRIDE_MAX 2.0        /* 200 % */
/* Axes groups: the command's axis field holds the group index. */
#define MC_OP_GROUP_CONFIGURE 16u   /* copy and validate group_config[group] (group disabled) */
#define MC_OP_APPLY_AXIS_FILTER 17u /* copy and validate axis_filter[axis] */
#define MC_OP_GROUP_ENABLE 18u      /* MC_GroupEnable */
#define MC_OP_GROUP_DISABLE 19u     /* MC_GroupDisable */
#define MC_OP_GROUP_STOP 20u        /* MC_GroupStop: args: dmax, jerk (along the path) */
#define MC_OP_GROUP_STOP_RELEASE 21u /* leave GroupStopping once at rest (MC_GroupStop Execute=FALSE) */
#define MC_OP_GROUP_RESET 22u       /* MC_GroupReset */
#define MC_OP_GROUP_HALT 23u        /* MC_GroupHalt: args: dmax, jerk */
#define MC_OP_GROUP_MOVE_LINEAR 24u /* MC_MoveLinear*: args: v, a, d, j, then one target per group axis */
#define MC_OP_GROUP_MOVE_CIRCULAR 25u /* MC_MoveCircular*: args: v, a, d, j, end_u, end_v, aux_u, aux_v, then the
                                       * helical targets of the group's other axes, in group order */
#define MC_OP_GROUP_MOVE_PTP 26u    /* synchronised point-to-point (Kim eq 10-14): args: v, a, d, j (per axis),
                                     * then one target per group axis. Flag MC_PTP_AXIS_LIMITS: each axis
                                     * also within the limits staged for it (the smaller wins) */
/* A NURBS curve reaches the card in continuation entries: BEGIN, DATA..., END, each answered by
 * its own ack or nack. The data stream is the control points (n_ctrl x group axes, in group
 * order, absolute counts), then the n_ctrl weights, then the n_knots knots. */
#define MC_OP_NURBS_BEGIN 27u /* args: degree, n_ctrl, n_knots, feed, accel, jerk, chord tolerance,
                               * saturation budget (0..1] ; flags: MC_MOVE_BUFFERED, MC_NURBS_SATURATION */
#define MC_OP_NURBS_DATA 28u  /* args: offset into the stream, count (1..12), then count values */
#define MC_OP_NURBS_END 29u   /* validate the curve and queue the move */
#define MC_NURBS_DATA_MAX 12u
/* Per-axis limits of the next MC_OP_GROUP_MOVE_PTP (any outcome consumes them; so do configure
 * and disable): args: first group axis, count (1..MC_PTP_LIMITS_MAX), then v, a, d, j of each */
#define MC_OP_GROUP_PTP_LIMITS 30u /* stage per-axis limits for the next MC_OP_GROUP_MOVE_PTP (above) */
/* Layout 1.5: MC_SetOverride of a group: args: feed factor (lines, arcs), rapid factor (MC_OP_GROUP_MOVE_PTP
 * moves), each 0..MC_OVERRIDE_MAX (else MC_NACK_OVERRIDE_RANGE). An S-curve feed is replanned from the
 * path's current speed and acceleration within the path limits (the geometry unchanged); a constant feed
 * (post-interpolation acc/dec) is scaled and smoothed by the filters. 0 holds the group still on its
 * path in Moving; a factor > 0 resumes. Reference-word arcs and NURBS curves run at their programmed
 * feed (the override applies from the next move). */
#define MC_OP_GROUP_SET_OVERRIDE 31u  /* MC_SetOverride of a group (above) */
#define MC_PTP_LIMITS_MAX 3u
#define MC_NURBS_SATURATION (1u << 2) /* saturation-aware feed (Yeh 3.4): needs PD+ axes */

/* Flags of the group move opcodes */
#define MC_MOVE_RELATIVE (1u << 0)
#define MC_MOVE_BUFFERED (1u << 1)     /* start when the queued moves end (else: a group must be at rest;
                                        * an axis aborts what it does) */
#define MC_CIRC_MODE_SHIFT 2u          /* 2 bits: */
#define MC_CIRC_BY_CENTRE 0u           /*   aux = centre */
#define MC_CIRC_BY_RADIUS 1u           /*   aux_u = radius (negative: the arc longer than half a turn) */
#define MC_CIRC_BY_BORDER 2u           /*   aux = a point on the arc (three-point circle) */
#define MC_CIRC_CCW (1u << 4)          /* else clockwise (ignored for border-point arcs) */
#define MC_CIRC_PLANE_SHIFT 5u         /* 2 bits: */
#define MC_PLANE_XY 0u                 /*   group axes 0, 1 */
#define MC_PLANE_YZ 1u                 /*   group axes 1, 2 */
#define MC_PLANE_ZX 2u                 /*   group axes 2, 0 */
#define MC_PLANE_AXES 3u               /*   any two group axes u, v, named apart (layout 1.10) */
#define MC_CIRC_U_SHIFT 22u            /* MC_PLANE_AXES: 3 bits, the plane's first group axis (u) */
#define MC_CIRC_V_SHIFT 25u            /* MC_PLANE_AXES: 3 bits, its second (v): counter-clockwise
                                        * turns from u towards v; u == v is MC_NACK_PLANE_AXES */
#define MC_CIRC_HELIX_RELATIVE (1u << 7) /* helical targets are distances even in an absolute move */
#define MC_FEED_TYPE_SHIFT 8u          /* 2 bits: the feed type selecting the acc/dec filters */
#define MC_FEED_RAPID 0u
#define MC_FEED_CUTTING 1u
#define MC_FEED_JOG 2u
#define MC_PTP_AXIS_LIMITS (1u << 10)  /* MC_OP_GROUP_MOVE_PTP: every axis's limits were staged (else
                                        * MC_NACK_BAD_CONFIG) */

/* group_config.accdec bits */
#define MC_ACCDEC_PRE (1u << 0)  /* S-curve of the tangential feed along the path */
#define MC_ACCDEC_POST (1u << 1) /* per-axis acc/dec filters after interpolation */

/* group_config.interpolator */
#define MC_INTERP_EXACT 0u          /* points exactly on the circle */
#define MC_INTERP_REFERENCE_WORD 1u /* Kim eq 15-23 for arcs (constant feed: needs MC_ACCDEC_POST only) */

/* axis_filter.kind[] */
#define MC_FILTER_NONE 0u        /* pass-through */
#define MC_FILTER_LINEAR 1u      /* moving average (linear acc/dec; Kim eq 1) */
#define MC_FILTER_EXPONENTIAL 2u /* first order (exponential acc/dec; Kim eq 7-9) */
#define MC_FILTER_BELL 3u        /* linear followed by exponential (bell-shaped; Shin eq 40) */
/* Safety opcodes (32..47). */
#define MC_OP_APPLY_SAFETY_CONFIG 32u /* copy and validate safety (axis field ignored) */
#define MC_OP_APPLY_AXIS_SAFETY 33u   /* copy and validate axis_safety[axis] */
#define MC_OP_ESTOP 34u               /* args: category (0, 1 or 2). Every axis; latched */
#define MC_OP_SAFETY_RESET 35u        /* clear the card-wide latches (watchdog, e-stop) once their
                                       * causes are gone; axes then leave ErrorStop by MC_OP_RESET */
/* Host sessions (layout 1.3). A host attaches before its first heartbeat and detaches when it
 * closes the card; a host that vanishes never detaches.
 *
 * The session gate (layout 1.8): the card takes a command that can start motion, give power,
 * change an output, a configuration or a latch only while a session is attached and its watchdog
 * armed; outside one it refuses it with MC_NACK_NO_SESSION and changes nothing. An attach arms
 * the watchdog (it counts as the host's first heartbeat), a detach disarms it, so a host that
 * attached is watched until it detaches. Taken without a session, being safe: MC_OP_NOP,
 * MC_OP_POWER_OFF, MC_OP_HALT, MC_OP_STOP, MC_OP_GROUP_HALT, MC_OP_GROUP_STOP,
 * MC_OP_GROUP_DISABLE, MC_OP_ESTOP, MC_OP_COMPARE_DISARM, MC_OP_PROBE_ABORT (they stop or remove
 * something), MC_OP_HOST_ATTACH, MC_OP_HOST_DETACH, MC_OP_READ_CONFIG, MC_OP_PROBE_ARM,
 * MC_OP_SCOPE_* (they read or observe), and data staged for a later command, starting nothing
 * itself: MC_OP_NURBS_BEGIN, MC_OP_NURBS_DATA, MC_OP_GROUP_PTP_LIMITS, MC_OP_PVT_POINTS,
 * MC_OP_CAM_TABLE, MC_OP_CAM_DATA. Every other opcode (and any opcode added later) is refused,
 * the configuration applies included: they change what the card does with the next motion or
 * with an axis holding position. Besides, the card itself stops (category 1, reason
 * MC_STOP_NO_SESSION) any motion it finds running with no session attached and armed: nothing
 * moves while nobody is in command. */
#define MC_OP_HOST_ATTACH 36u /* flags: the new session id (nonzero). If another session is still
                               * attached (its host died or hung without detaching), every enabled
                               * axis makes a category 1 stop with reason MC_STOP_HOST_CHANGED: a
                               * new host never inherits motion it did not start. The ack's value
                               * is the number of axes that stop made. The attach arms the
                               * watchdog: its heartbeat must come within the watchdog timeout. */
#define MC_OP_HOST_DETACH 37u /* flags: the session id. A clean close: every moving axis and group
                               * halts along its axis stop ramp (reason MC_STOP_HOST_DETACH, no
                               * fault latched) and the watchdog is disarmed until the next
                               * attach (later heartbeats do not arm it); until then the session
                               * gate refuses motion (MC_NACK_NO_SESSION). MC_NACK_SESSION if
                               * another session is attached. */

/* Homing opcodes (48..55, layout 1.5): PLCopen MC_Home with the CiA 402 homing methods, and
 * MC_SetPosition. Positions are in the axis's own frame: the card counts encoder counts plus an
 * offset that homing and MC_SetPosition set (the raw count in the status never jumps, so the
 * encoder checks of the safety layer see only the shaft).
 *
 * Convention: homing finds a home point (a switch edge, an index pulse, a hard stop, or the
 * current position) and sets the position so that the home point reads
 *     MC_OP_HOME's position argument + axis_homing[axis].home_offset
 * (as CiA 402 drives set their actual position to the home offset at the home point). With
 * MC_HOMING_MOVE_TO_HOME the axis then ends at the home point; otherwise where it came to rest
 * after finding it. Motion done (MC_EV_MOTION_DONE with the MC_Home's seq) once homed and in
 * position; a failure is MC_EV_HOMING_FAILED, the axis at rest in Standstill, not homed. The axis
 * is in PLCopen Homing meanwhile: moves, jogs and another MC_Home are refused
 * (MC_NACK_AXIS_HOMING); MC_OP_HALT and MC_OP_STOP abort it (MC_EV_MOTION_ABORTED). Homing runs
 * at its own limits; the override does not scale them. Soft limits take effect once the axis is
 * homed (MC_MOTION_HOMED): homing clears the bit while it runs.
 *
 * axis_homing.method, the CiA 402 numbers (the home point; "index": the first index pulse
 * beyond it in the direction of the final approach, which is always made at the creep
 * velocity from the same side):
 *   1, 2    the edge of the negative (1) or positive (2) limit switch, then the index. From a
 *           position on that limit switch the axis creeps off it directly
 *   3, 4    a home switch active above its edge, then the index below (3) or above (4) it
 *   5, 6    a home switch active below its edge, then the index above (5) or below (6) it
 *   7..14   a home switch with a lower and an upper edge, then the index: 7 below the lower
 *           edge, 8 above it, 9 below the upper edge, 10 above it, starting in the positive
 *           direction; 11 above the upper edge, 12 below it, 13 above the lower edge, 14 below
 *           it, starting in the negative direction. A limit switch met before the home switch
 *           reverses the search once
 *   17..30  as 1..14 without the index: the home point is the switch edge
 *   33, 34  the next index pulse in the negative (33) or positive (34) direction
 *   35, 37  the current position (nothing moves)
 *   -1, -2  a hard stop (a mechanical end stop) in the negative (-1) or positive (-2)
 *           direction, approached at the creep velocity and detected as a following error of at
 *           least hard_stop_ferror held for hard_stop_dwell, then the index away from it
 *   -3, -4  the same hard stop without the index: the home point is where the axis stalled
 * Methods with limit switches in their definition (1, 2, 7..14, 17, 18, 23..30) watch both limit
 * switches themselves: the safety layer does not trip on them while the axis homes, the method
 * reverses where CiA 402 says so, and any other limit switch ends homing with
 * MC_HOMING_ERR_LIMIT. Under the other methods a limit switch is unexpected and trips the safety
 * layer as always. */
#define MC_OP_APPLY_AXIS_HOMING 48u /* copy and validate axis_homing[axis] */
#define MC_OP_HOME 49u              /* MC_Home: args: position (what the home point reads, before
                                     * the home offset). From Standstill */
#define MC_OP_SET_POSITION 50u      /* MC_SetPosition: args: position; flags: MC_SET_POSITION_RELATIVE.
                                     * The actual and commanded positions become position (relative:
                                     * move by it) without moving; sets MC_MOTION_HOMED. Standstill or
                                     * Disabled */
#define MC_SET_POSITION_RELATIVE (1u << 0)

/* Continuous path opcodes (56..63, layout 1.6). Each group has a path buffer on the card of
 * MC_PATH_LEN segments: lines, arcs and helices, and dwells, each with a user id (args[0], an
 * integer 0..2^32-1). The card looks ahead by distance (as far as braking takes), blends
 * the corners within each segment's tolerance (a curvature-continuous blend: acceleration is
 * continuous through the corner) and runs a jerk-limited tangential feed within every axis's
 * velocity, acceleration and jerk limit (group_path[group].vmax, amax, jmax). It can always
 * brake within what is queued: when the buffer runs dry the path comes to rest at the end of
 * the last segment (MC_EV_PATH_STARVED unless that segment carries MC_PATH_LAST) and resumes
 * from there when more arrives. Events: MC_EV_SEGMENT_START / _END as each segment starts and
 * ends (value: its id, seq: its command), MC_EV_PATH_LOW_WATER, MC_EV_GROUP_MOTION_DONE (seq:
 * the last segment) once the path is at rest in position, MC_EV_GROUP_MOTION_ABORTED per
 * segment a halt, stop or fault drops. A path needs pre-interpolation acc/dec only (no
 * post-interpolation filters: MC_NACK_INCOMPATIBLE_MODE) and does not mix with the group's
 * move queue (MC_NACK_PATH_BUSY). MC_OP_GROUP_HALT and _STOP stop along the path. */
#define MC_PATH_LEN 4096u            /* segments in a group's path buffer */
#define MC_OP_PATH_LINE 56u          /* args: id, feed, tolerance, then one target per group axis.
                                      * flags: MC_MOVE_RELATIVE, MC_PATH_* */
#define MC_OP_PATH_ARC 57u           /* args: id, feed, tolerance, end_u, end_v, aux_u, aux_v (as
                                      * MC_OP_GROUP_MOVE_CIRCULAR), then the targets of the other
                                      * group axes in order (a helix). flags: MC_MOVE_RELATIVE,
                                      * MC_CIRC_*, MC_PATH_* */
#define MC_OP_PATH_DWELL 58u         /* args: id, seconds (0 < t <= MC_MAX_MOVE_TIME): an exact stop,
                                      * then a wait. flags: MC_PATH_LAST */
#define MC_OP_PATH_OUTPUT 59u        /* args: output (0..MC_OUTPUTS-1), on (0 or 1), distance. flags:
                                      * MC_PATH_OUT_*. Sets or clears the output when the next
                                      * motion segment queued starts, ends, or has run `distance`
                                      * counts; at most MC_PATH_OUTPUTS_PENDING before that segment */
#define MC_OP_APPLY_GROUP_PATH 60u   /* copy and validate group_path[group] (path empty and at rest) */
#define MC_OP_SET_OUTPUTS 61u        /* args: mask, value (0..2^MC_OUTPUTS-1): set the outputs in
                                      * mask to value now (axis field ignored) */
#define MC_OP_PATH_NURBS 62u         /* a NURBS curve as one path segment: args: id, feed, tolerance,
                                      * degree, n_ctrl, n_knots, fit tolerance (> 0: the largest
                                      * distance of the commanded path from the curve, counts).
                                      * flags: MC_MOVE_RELATIVE (control points from the path's
                                      * end), MC_PATH_* (a time-shifted transition is refused).
                                      * The curve follows in MC_OP_NURBS_DATA entries and is queued
                                      * by MC_OP_NURBS_END, as a NURBS move; it must start within
                                      * the fit tolerance of the path's end (MC_NACK_NURBS_START).
                                      * On the card it takes one buffer entry per piece: quintics
                                      * fitted to the curve, curvature-continuous where it is
                                      * (MC_NACK_QUEUE_FULL until they fit; MC_NACK_PATH_CURVE) */
#define MC_OUTPUTS 16u               /* the card's digital outputs (card.outputs) */
#define MC_PATH_OUTPUTS_PENDING 8u
/* Digital I/O, position compare and touch probes (opcodes 64..79, layout 1.7).
 *
 * Inputs: MC_INPUTS digital inputs. The card samples them every tick; io_config (applied by
 * MC_OP_APPLY_IO_CONFIG) inverts the active-low ones (polarity) and debounces each: the
 * debounced bit takes a new level once the input has held it for debounce[i] ticks (0: at
 * once). card.inputs_raw is the sample (polarity applied), card.inputs the debounced word; an
 * edge of the debounced word whose bit is in rise_events / fall_events posts MC_EV_INPUT.
 *
 * Position compare ("EQU" outputs): MC_COMPARE_CHANNELS channels, each watching one axis's
 * ACTUAL position and pulsing one digital output (pulse_us wide) when the position crosses a
 * compare position in the channel's direction: a single position, a linear series
 * (start + k * pitch, k = 0..count-1, pitch signed by the direction), or a table of positions
 * streamed in with MC_OP_COMPARE_TABLE (MC_COMPARE_TABLE_LEN queued at most, strictly
 * monotonic in the direction). The firing instant is found within the tick the way the
 * encoder interface's comparator does it: between the counts at the tick's two ends, taking
 * a count n as the middle of its cell (n + 0.5). A position already passed when it becomes
 * the next one (armed behind the axis, or queued too late), or whose instant falls inside the
 * pulse before it (the output is still on), is missed: counted and reported, never fired.
 * The output is on in card.outputs from the tick that detects a fire for
 * ceil(pulse_us * rate) ticks (at least one); a channel's pulse ORs with the host's outputs.
 *
 * Layout 1.13, compare on a modulo (rotary) axis of period m (the axis's when the channel is
 * armed): every compare position is a place on the turn, 0 <= p < m (else
 * MC_NACK_COMPARE_TURN), and fires whenever the axis crosses p + j * m for any whole j, in
 * the channel's direction, with the instant found as above (across the wrap as anywhere:
 * the counts at the tick's ends are taken in one frame, the axis's whole turns kept apart
 * exactly, so nothing drifts however many turns the axis has made). Nothing on a modulo
 * axis is ever behind: a position comes round again, and the channel waits for it. Misses
 * are those of a pulse still on and of a crossing undone within the tick.
 * - A single position fires at the next crossing and is done; with MC_CMP_EACH_TURN it fires
 *   at every crossing, on every turn, until MC_OP_COMPARE_DISARM (a single either way: each
 *   crossing either way).
 * - A series: its positions are start + k * pitch wrapped into [0, m), k = 0..count-1, all
 *   within one turn ((count - 1) * pitch < m, else MC_NACK_COMPARE_TURN); each fires at the
 *   axis's next crossing of it after the one before, in order, so a series may run over the
 *   wrap (start 350, pitch 10, count 3: 350, 0, 10). Without MC_CMP_EACH_TURN it is done
 *   after its last; with it the series is a set of places on the turn, each fired at every
 *   crossing, endless, whichever the axis comes to (back and forth as well) (count * pitch <=
 *   m, else MC_NACK_COMPARE_TURN; count 0: floor(m / pitch) positions, a whole turn of
 *   pitches, every pitch around the turn when pitch divides m).
 * - A table: positions in [0, m) (MC_NACK_COMPARE_TURN), each fired once at the axis's next
 *   crossing of it after the one before; while the channel is armed on a modulo axis they may
 *   come in any order (the next equal to the last: a turn later), before the arm the linear
 *   rule (strictly monotonic) holds and the arm checks the queue is in [0, m).
 *   MC_CMP_EACH_TURN on a table: MC_NACK_COMPARE_MODE (a table is consumed).
 * compare_status on an endless channel (MC_CMP_EACH_TURN): pending is the positions in a
 * turn, state stays MC_IO_ARMED; next, last_fired and last_missed are places on the turn.
 * MC_OP_SET_MODULO on an axis an armed compare channel watches (not done) is refused,
 * MC_NACK_COMPARE_TURN: disarm first.
 *
 * Touch probe (PLCopen MC_TouchProbe / MC_AbortTrigger): MC_PROBE_CHANNELS channels, each
 * capturing one axis's position at an edge of an input (raw, polarity applied, not debounced:
 * the encoder interface timestamps the edge within the tick) or at the axis's encoder index
 * pulse (input MC_PROBE_INDEX: the exact count latched). The position at the edge is
 * interpolated between the counts at the tick's two ends as the comparator does. With
 * MC_PROBE_WINDOW only edges whose position lies in [window_lo, window_hi] count. Single shot
 * ends after the first capture; continuous keeps capturing into probe_status's queue.
 * With MC_PROBE_HALT (layout 1.9, a probing move: G38) the capture halts the axis's motion in
 * the tick it is detected, by the card and not the host: the axis's group halts along its
 * path (MC_GroupHalt on the members' stop ramps, queued path dropped), or the axis alone on its
 * stop ramp; the axes' stop reason is MC_STOP_PROBE. Nothing moving: nothing to halt. */
#define MC_INPUTS 16u                /* the card's digital inputs (card.inputs) */
#define MC_DEBOUNCE_MAX 10000u       /* io_config.debounce, ticks */
#define MC_COMPARE_CHANNELS 4u
#define MC_COMPARE_TABLE_LEN 4096u   /* positions queued per compare channel */
#define MC_COMPARE_TABLE_MAX 12u     /* positions per MC_OP_COMPARE_TABLE entry */
#define MC_PULSE_MAX_US 1000000u     /* pulse_us: 1..MC_PULSE_MAX_US */
#define MC_PROBE_CHANNELS 4u
#define MC_PROBE_QUEUE 8u            /* captures kept in probe_status (a ring) */
#define MC_PROBE_INDEX 16u           /* probe input: the axis's encoder index pulse */
#define MC_OP_APPLY_IO_CONFIG 64u    /* copy and validate io_config (axis field ignored) */
#define MC_OP_COMPARE_ARM 65u        /* axis: the axis watched. args: channel, output
                                      * (0..MC_OUTPUTS-1), pulse_us, low_water (table: the
                                      * MC_EV_COMPARE low-water mark, 0: none), position (single)
                                      * or start (series), pitch (series, counts, >= 1), count
                                      * (series, 1..2^31-1). flags: MC_CMP_MODE_* and MC_CMP_DIR_*.
                                      * MC_NACK_COMPARE_BUSY if the channel is armed (a channel
                                      * done may be armed again) or another armed channel pulses
                                      * that output. A table channel fires
                                      * what was queued before (MC_OP_COMPARE_TABLE) and what is
                                      * queued after; its queue is kept from one arm to the next
                                      * until MC_OP_COMPARE_DISARM */
#define MC_OP_COMPARE_TABLE 66u      /* args: channel, n (1..MC_COMPARE_TABLE_MAX), then n positions
                                      * (strictly beyond the last queued in the direction, else
                                      * MC_NACK_COMPARE_ORDER; no room: MC_NACK_COMPARE_FULL, none
                                      * taken). flags: MC_CMP_DIR_POS or _NEG (the table's; the
                                      * arm must agree). Ack value: the free room after */
#define MC_OP_COMPARE_DISARM 67u     /* args: channel. Stops the channel, drops its table, ends
                                      * its pulse */
#define MC_OP_PROBE_ARM 68u          /* MC_TouchProbe. axis: the axis captured. args: channel,
                                      * input (0..MC_INPUTS-1 or MC_PROBE_INDEX), window_lo,
                                      * window_hi. flags: MC_PROBE_RISING / _FALLING (one or
                                      * both), MC_PROBE_CONTINUOUS, MC_PROBE_WINDOW. Re-arming
                                      * restarts the channel */
#define MC_OP_PROBE_ABORT 69u        /* MC_AbortTrigger. args: channel */
/* MC_OP_COMPARE_ARM flags */
#define MC_CMP_MODE_SINGLE 0u
#define MC_CMP_MODE_SERIES 1u
#define MC_CMP_MODE_TABLE 2u
#define MC_CMP_MODE_MASK 3u
#define MC_CMP_DIR_POS (1u << 2)     /* fire crossing upwards */
#define MC_CMP_DIR_NEG (1u << 3)     /* fire crossing downwards (single: both bits, either way) */
#define MC_CMP_EACH_TURN (1u << 4)   /* layout 1.13, a modulo axis only (else MC_NACK_COMPARE_TURN):
                                      * a single position or a series fires on every turn,
                                      * endless (see above) */
/* mc_compare_status.state, mc_probe_status.state */
#define MC_IO_IDLE 0u                /* not armed */
#define MC_IO_ARMED 1u               /* armed: watching or capturing */
#define MC_IO_DONE 2u                /* a single compare or series fired (or missed) all; a
                                      * single-shot probe captured */
/* MC_OP_PROBE_ARM flags */
#define MC_PROBE_RISING (1u << 0)    /* capture as the input becomes active */
#define MC_PROBE_FALLING (1u << 1)   /* capture as the input becomes inactive */
#define MC_PROBE_CONTINUOUS (1u << 2)
#define MC_PROBE_WINDOW (1u << 3)
#define MC_PROBE_HALT (1u << 4)      /* a capture halts the axis's group or the axis (layout 1.9) */
/* MC_EV_COMPARE codes. At most one event of each code per channel per tick: value is the
 * last position of that tick; compare_status counts every one */
#define MC_CMP_FIRED 1               /* a position fired */
#define MC_CMP_MISSED 2              /* a position missed: passed when it became the next one,
                                      * or inside the pulse before it */
#define MC_CMP_LOW_WATER 3           /* the table's queue fell to low_water; value: queued */

/* MC_OP_PATH_LINE / _ARC flags */
#define MC_PATH_BUFFER_SHIFT 16u     /* 3 bits, PLCopen BufferMode: how the segment joins the one
                                      * before: */
#define MC_PATH_ABORTING 0u          /*   the path stops along its geometry within its limits, the
                                      *   rest is aborted, and this segment starts from there */
#define MC_PATH_BUFFERED 1u          /*   exact stop at the corner, then this segment */
#define MC_PATH_BLEND_LOW 2u         /*   blend; corner speed <= the lower of the two feeds */
#define MC_PATH_BLEND_PREVIOUS 3u    /*   blend; corner speed <= the previous segment's feed */
#define MC_PATH_BLEND_NEXT 4u        /*   blend; corner speed <= this segment's feed */
#define MC_PATH_BLEND_HIGH 5u        /*   blend; corner speed <= the higher of the two feeds */
#define MC_PATH_TRANSITION_SHIFT 19u /* 2 bits, PLCopen TransitionMode of a blend: */
#define MC_TM_NONE 0u                /*   no blend: an exact stop at the corner */
#define MC_TM_MAX_DEVIATION 1u       /*   the blend keeps within `tolerance` counts of the corner */
#define MC_TM_CORNER_DISTANCE 2u     /*   the blend begins `tolerance` counts before the corner */
#define MC_TM_TIME_SHIFT 3u          /*   Thinh's blending of two lines: each runs as its own
                                      *   rest-to-rest S-curve, this one starting while the one
                                      *   before decelerates, within `tolerance` counts of the
                                      *   corner; refused (MC_NACK_PATH_MODE) on or after an arc,
                                      *   and a blend after such a line is refused too */
#define MC_PATH_LAST (1u << 21)      /* the last segment of a program: its stop is not starvation */
/* MC_OP_PATH_OUTPUT flags: when */
#define MC_PATH_OUT_AT_START 0u      /* as the segment starts */
#define MC_PATH_OUT_AT_END 1u        /* as the segment ends */
#define MC_PATH_OUT_AT_DISTANCE 2u   /* once the segment has run `distance` counts */
/* Path status bits (mc_group_status_payload.path_flags) */
#define MC_PATHST_RUNNING (1u << 0)  /* a segment is running (path_id is valid) */
#define MC_PATHST_STARVING (1u << 1) /* braking for the end of what is queued */
#define MC_PATHST_HALTING (1u << 2)  /* a halt or stop runs along the path */
#define MC_PATHST_PAUSING (1u << 3)  /* layout 1.11: braking for the pause point (MC_OP_PATH_PAUSE) */
#define MC_PATHST_PAUSED (1u << 4)   /* at rest on the pause point (path_id: the segment it ends) */
/* Layout 1.11: MC_OP_PATH_PAUSE (args: 1 pause, 0 go on; else MC_NACK_OUT_OF_RANGE, NaN:
 * MC_NACK_NOT_FINITE). A pause comes to rest at the end of the first segment the path can stop
 * at within its limits from where it is (an exact stop or a dwell's end ahead, or the first
 * segment end beyond the braking distance; at rest with nothing queued, at once): at the end of
 * the segment's body, which is its programmed end where no blend follows it and the start of
 * the blend into the next segment (within the segment's tolerance of its programmed end) where
 * one does. Nothing queued changes, segments may still be queued, and after 0 the path goes on
 * along the same geometry from rest (0 before the pause point is reached: the path does not
 * stop there). MC_EV_PATH_PAUSED posts on coming to rest there; the status shows
 * MC_PATHST_PAUSING, then MC_PATHST_PAUSED. A halt, stop or fault ends the pause (the path is
 * dropped as by any halt); a pause while halting is MC_NACK_INVALID_STATE; without a path
 * (MC_OP_APPLY_GROUP_PATH not done) MC_NACK_INVALID_STATE too. */
#define MC_OP_PATH_PAUSE 120u /* args: 1 pause at the end of a segment, 0 go on (above) */

/* Layout 1.12: several cards on one servo clock (the sync bus), and commands timed to a tick.
 *
 * The sync bus: one card is the clock master; the others (followers) run their servo tick on
 * the master's, as a sync cable would drive them, and carry its tick count, so a tick number
 * means the same instant on every card of the bus. The bus also carries the master's commits
 * (below). A follower that loses the master (no tick within MC_BUS_LOSS_TICKS periods, or the
 * bus gone) halts every moving axis and group along its stop ramp (reason MC_STOP_SYNC_LOST),
 * refuses what it holds timed (MC_NACK_SYNC_LOST), posts MC_EV_SYNC_BUS (MC_BUSST_LOST) and runs on
 * its own clock. card_info (appended) shows the role and state.
 *
 * A timed command is two ring entries published together: MC_OP_AT_TICK, then the command it
 * times (any opcode but MC_OP_AT_TICK, the session and commit opcodes). MC_OP_AT_TICK is
 * answered at once: its ack means the pair is held for that tick; its nack (MC_NACK_TICK_PASSED,
 * MC_NACK_TIMED_FULL, MC_NACK_TIMED_ALONE, MC_NACK_TICK_FAR, or any refusal of the command
 * when decoded: its code) also nacks the command (MC_NACK_TIMED_REFUSED, or the same code). The
 * command itself is answered on its tick, the first thing that tick does: executed (its ack or
 * nack then), or, with a key whose commit the card has not seen, MC_NACK_NOT_COMMITTED,
 * executing nothing. Key 0 needs no commit. A commit (MC_OP_SYNC_COMMIT) goes to the master
 * alone, before the tick (master's tick < tick): it reaches every follower with the ticks, so
 * that either every card of the bus runs the commands of that key on their tick or none does.
 * MC_OP_TIMED_CANCEL drops the held commands of a key (MC_NACK_CANCELLED each). A host's detach
 * or a lost session drops them too (MC_NACK_CANCELLED). */
#define MC_OP_AT_TICK 126u      /* args: tick (the card tick to run the next entry on: > the card's
                                 * tick, within MC_TIMED_MAX_AHEAD ticks), key (0: none, else
                                 * 1..2^32-1: run only once MC_OP_SYNC_COMMIT of it is seen) */
#define MC_OP_SYNC_COMMIT 127u  /* args: key (1..2^32-1), tick (the commands' tick). On the bus's
                                 * master or a card alone: MC_NACK_COMMIT_LATE unless tick > the
                                 * card's tick; a follower: MC_NACK_NOT_MASTER */
#define MC_OP_TIMED_CANCEL 128u /* args: key (0: every held command). Ack value: the commands
                                 * dropped */
#define MC_TIMED_SLOTS 16u           /* timed commands a card holds at once */
#define MC_TIMED_MAX_AHEAD 600000u   /* the farthest a timed command may look ahead, ticks */
#define MC_BUS_LOSS_TICKS 200u      /* periods a follower waits for the master's tick */

/* card_info.sync_role */
#define MC_BUS_ALONE 0u    /* on its own clock, no bus */
#define MC_BUS_MASTER 1u   /* drives the bus */
#define MC_BUS_FOLLOWER 2u /* runs on the bus's ticks */
/* card_info.sync_state (and the codes of MC_EV_SYNC_BUS) */
#define MC_BUSST_FREE 0u   /* alone or master: its own clock */
#define MC_BUSST_LOCKED 1u /* a follower on the master's ticks */
#define MC_BUSST_LOST 2u   /* a follower that lost the master: its own clock, halted */

/* mc_axis_homing.flags */
#define MC_HOMING_INDEX (1u << 0)        /* the encoder has an index channel (index methods need it) */
#define MC_HOMING_MOVE_TO_HOME (1u << 1) /* end at the home point */

/* MC_EV_HOMING_FAILED codes */
#define MC_HOMING_ERR_LIMIT 1    /* a limit switch the method did not reverse at: the switch is missing */
#define MC_HOMING_ERR_DISTANCE 2 /* max_distance from the start without the switch or hard stop */
#define MC_HOMING_ERR_TIMEOUT 3  /* not homed within the timeout */
#define MC_HOMING_ERR_NO_INDEX 4 /* no index pulse within index_distance */
#define MC_HOMING_ERR_PLAN 5     /* a motion of the method could not be planned */

/* layout 1.7 (sync): synchronised motion. Opcodes 80..95, nack codes 100..109, event kinds 27
 * and 28 (their sub-cases in the event's code).
 *
 * Electronic gearing (PLCopen MC_GearIn, MC_GearInPos, MC_GearOut). The slave is the command's
 * axis; its master is another axis's commanded or actual position, or an auxiliary encoder input
 * (flags: MC_MASTER_*; args[0]: the master axis or aux encoder number). The ratio is an integer
 * numerator / a positive integer denominator, both of magnitude 1..MC_GEAR_RATIO_MAX (else
 * MC_NACK_GEAR_RATIO): slave counts per master count. The card computes the slave's position from
 * the master's count in integer arithmetic, quotient and remainder of numerator x (master -
 * anchor) / denominator, so nothing drifts however long the coupling runs (a commanded master
 * counts in 1/65536 of a count). The slave is in SynchronizedMotion from the command on; it
 * catches up within its own vmax, amax and jerk (args), then MC_EV_SYNC (code MC_SYNC_IN_GEAR /
 * MC_SYNC_IN_SYNC, seq: the gear command) and MC_MOTION_IN_SYNC in its status. A master that is
 * disabled or in ErrorStop: the slave stops on its stop ramp (MC_EV_SYNC code
 * MC_SYNC_MASTER_LOST, MC_EV_MOTION_ABORTED for the gear command, the axis Stopping then
 * Standstill). Halt, stop and the safety stops end the coupling as any motion; the override does
 * not scale a coupled slave (it follows its master). A commanded master is followed in the same
 * servo tick (its reference is computed before the slaves'; one driven by homing or a PT/PVT
 * stream: a tick late). An actual-position master is the encoder latched at the tick's start,
 * which the slave's servo reaches a tick later: the slave trails it by ratio x v x Ts, unless
 * the master is MC_MASTER_ACTUAL_LEAD (layout 1.9), the encoder led by its velocity estimate
 * over one servo period. */
#define MC_OP_GEAR_IN 80u     /* args: master, numerator, denominator, vmax, amax, jerk. flags:
                               * MC_MASTER_*. Aborting; from Standstill, DiscreteMotion,
                               * ContinuousMotion or SynchronizedMotion (a new ratio). The
                               * ack's value (and MC_OP_GEAR_IN_POS's): the coupling's offset,
                               * slave counts with the master at 0 (in gear: slave = offset +
                               * ratio x master, counts; anchored where both were at the
                               * engagement, or at the sync point) */
#define MC_OP_GEAR_IN_POS 81u /* as MC_OP_GEAR_IN, then args: master sync position, slave sync
                               * position: the slave reaches the slave position exactly when the
                               * master reaches the master position, along a quintic in the
                               * master's position (velocity and acceleration continuous), checked
                               * against vmax, amax, jerk at the master's present velocity (else
                               * MC_NACK_INFEASIBLE; a master at rest or moving away: the same) */
#define MC_OP_GEAR_OUT 82u    /* MC_GearOut: the slave leaves the coupling in velocity mode at its
                               * velocity (ContinuousMotion, MC_EV_IN_VELOCITY with this command's
                               * seq), its acceleration ramped to 0 within the gear's amax and
                               * jerk; stop it with MC_OP_HALT. The gear command: MC_EV_MOTION_ABORTED
                               * (code MC_OP_GEAR_OUT) */
#define MC_MASTER_COMMANDED 0u /* flags: the master axis's commanded position */
#define MC_MASTER_ACTUAL 1u    /* the master axis's actual position (its encoder) */
#define MC_MASTER_AUX 2u       /* an auxiliary encoder input (0..MC_AUX_ENCODERS-1) */
#define MC_MASTER_ACTUAL_LEAD 3u /* the master axis's actual position led by one servo period
                                  * (encoder + v x Ts, v its velocity estimate), in 1/65536
                                  * count: no tick of lag at a constant velocity (layout 1.9) */
#define MC_AUX_ENCODERS 2u     /* auxiliary encoder inputs of the card (conveyor, handwheel) */
#define MC_GEAR_RATIO_MAX 2147483647.0 /* |numerator|, denominator <= 2^31 - 1 */
#define MC_EV_SYNC 27u         /* synchronised motion. axis: the slave; seq: the gear command;
                                * code: MC_SYNC_*; value: the slave's commanded position (master
                                * lost: the master's number) */
#define MC_SYNC_IN_GEAR 1      /* MC_GearIn caught up: the slave follows the ratio (InGear) */
#define MC_SYNC_IN_SYNC 2      /* MC_GearInPos reached its sync point (InSync) */
#define MC_SYNC_MASTER_LOST 3  /* the master is disabled or in ErrorStop: the slave stops */
#define MC_EV_PVT 28u          /* a PT/PVT stream. axis: the axis; seq: its MC_OP_PVT_START; code:
                                * MC_PVT_EV_*; value: the points queued (low water), the time of
                                * the last point run (starved), the last position (done) */
#define MC_PVT_EV_LOW_WATER 1  /* the points queued fell to the stream's low water */
#define MC_PVT_EV_STARVED 2    /* the stream ran dry before a last point: the axis stops on its stop
                                * ramp (Stopping, then Standstill; MC_EV_MOTION_ABORTED) */
#define MC_PVT_EV_DONE 3       /* the last point was reached (motion done follows in position) */
#define MC_NACK_GEAR_RATIO 100 /* a ratio that is not integer, a zero numerator, a denominator <= 0,
                                * or a magnitude above MC_GEAR_RATIO_MAX */
#define MC_NACK_SYNC_MASTER 101 /* a master source the card does not know, a master axis or aux
                                 * encoder it does not have, the slave itself, or a master axis
                                 * disabled or in ErrorStop */
#define MC_MOTION_IN_SYNC (1u << 8) /* layout 1.7 (sync): the slave follows its master (InGear) */

/* layout 1.7 (sync): PT/PVT streaming (Googol GTS and Delta Tau PVT). Each axis has a buffer of
 * MC_PVT_LEN points on the card. MC_OP_PVT_BEGIN (from Standstill) opens a stream at the axis's
 * commanded position, at rest, at time 0; MC_OP_PVT_POINTS appends points (time from the start,
 * strictly increasing by at least one servo period; position; velocity), MC_OP_PVT_START runs it
 * (SynchronizedMotion). Between two points the position is the cubic Hermite segment through
 * both positions and velocities: it passes exactly through every point, velocity continuous. PT
 * (MC_PVT_PT): the velocity at a point is the three-point estimate from its neighbours
 * ((d- h+ + d+ h-)/(h- + h+), d the chords' slopes, h their durations), known when the next
 * point arrives; a point marked MC_PVT_LAST ends at rest. Every segment is checked against the
 * stream's vmax and amax when its end velocity is known, and the point that breaks them is
 * refused (MC_NACK_PVT_LIMIT), the command's points all or none. A stream that runs dry before
 * its last point stops on the axis's stop ramp (MC_PVT_EV_STARVED); the last point reached:
 * MC_PVT_EV_DONE, motion done (MC_OP_PVT_START's seq) once in position, Standstill. Halt, stop
 * and safety stops end the stream. */
#define MC_OP_PVT_BEGIN 83u   /* args: vmax, amax, low water (points, 0: none). flags: MC_PVT_PT.
                               * Standstill, no stream running (else MC_NACK_PVT_SEQUENCE) */
#define MC_OP_PVT_POINTS 84u  /* args: count (1..MC_PVT_POINTS_MAX), then time, position, velocity
                               * of each (PT: velocity ignored). flags: MC_PVT_LAST (the last of
                               * these is the stream's last). Ack value: the points still free */
#define MC_OP_PVT_START 85u   /* args: axis mask (bit i: axis i; 0: this axis): the streams of
                               * every axis in it start on the same tick */
#define MC_PVT_PT (1u << 0)
#define MC_PVT_LAST (1u << 1)
#define MC_PVT_LEN 4096u      /* points buffered per axis */
#define MC_PVT_POINTS_MAX 4u  /* points per MC_OP_PVT_POINTS */
#define MC_NACK_PVT_TIME 102  /* a point not at least one servo period after the one before, or a
                               * segment longer than MC_MAX_MOVE_TIME */
#define MC_NACK_PVT_LIMIT 103 /* a point whose segment breaks the stream's vmax or amax, or a last
                               * point (PVT) with a velocity */
#define MC_NACK_PVT_SEQUENCE 104 /* points without an open stream or after its last point, a start
                                  * without points or on an axis that moved, a begin while one runs */

/* layout 1.7 (sync): camming (PLCopen MC_CamTableSelect, MC_CamIn, MC_CamOut). The card holds
 * MC_CAM_TABLES tables of up to MC_CAM_MAX_POINTS points (master, slave) in its own RAM, loaded
 * with commands: MC_OP_CAM_TABLE opens a table, MC_OP_CAM_DATA sends its points in order, and
 * the table is built once its last point arrived (master positions strictly increasing, all
 * finite; a table in use by a slave cannot be reloaded). Linear or cubic-spline interpolation
 * (MC_CAM_CUBIC: velocity and acceleration continuous; natural ends, or periodic), periodic or
 * not (MC_CAM_PERIODIC: the master's period is the table's span, the slave may rise by its last
 * minus first point per cycle). MC_OP_CAM_IN couples a slave as MC_OP_GEAR_IN does (catch-up
 * within vmax, amax, jerk, then MC_EV_SYNC MC_SYNC_IN_SYNC): slave = slave offset + slave scale
 * x table((master - master offset) / master scale). With MC_CAM_AT_CYCLE_END on a cammed slave
 * the new table takes over at the end of the current cycle, the slave's position continuous
 * (MC_SYNC_CAM_SWITCH). A table that is not periodic ends: the slave holds its end
 * (MC_SYNC_CAM_END). MC_OP_GEAR_OUT (or MC_OP_CAM_OUT) leaves the cam in velocity mode. */
#define MC_OP_CAM_TABLE 86u   /* args: table, points (2..MC_CAM_MAX_POINTS; cubic: 3..). flags:
                               * MC_CAM_CUBIC, MC_CAM_PERIODIC. Any axis */
#define MC_OP_CAM_DATA 87u    /* args: table, index of the first point, count (1..MC_CAM_DATA_MAX),
                               * then master, slave of each */
#define MC_OP_CAM_IN 88u      /* args: master, table, master offset, slave offset, master scale,
                               * slave scale, vmax, amax, jerk. flags: MC_MASTER_* |
                               * MC_CAM_AT_CYCLE_END */
#define MC_OP_CAM_OUT 89u     /* as MC_OP_GEAR_OUT */
#define MC_CAM_TABLES 4u
#define MC_CAM_MAX_POINTS 1024u
#define MC_CAM_DATA_MAX 5u
#define MC_CAM_CUBIC (1u << 0)        /* a cubic spline: velocity and acceleration continuous
                                       * (else linear) */
#define MC_CAM_PERIODIC (1u << 1)     /* periodic: the master's period is the table's span */
#define MC_CAM_AT_CYCLE_END (1u << 4) /* MC_OP_CAM_IN flag (beside the master source) */
#define MC_CAM_RELATIVE (1u << 5) /* MC_OP_CAM_IN flag: PLCopen StartMode relative. The slave
                                   * offset is shifted by where the slave stands minus where the
                                   * table puts it at the master's present position, so the cam
                                   * starts from the slave's position (only a velocity difference
                                   * is caught up). Without it: absolute, ramped in. Ignored with
                                   * MC_CAM_AT_CYCLE_END (a switch continues the slave anyway). */
#define MC_SYNC_CAM_END 4     /* MC_EV_SYNC: a cam that is not periodic passed its table's end */
#define MC_SYNC_CAM_SWITCH 5  /* MC_EV_SYNC: the table switched at the end of a cycle (seq: the
                               * MC_OP_CAM_IN that asked for it) */
#define MC_NACK_CAM_TABLE 105 /* a table number, point count or flags out of range, points not
                               * strictly increasing in the master or not finite, a table not
                               * loaded, or one in use */
#define MC_NACK_CAM_SEQUENCE 106 /* cam data without an open table or out of order */

/* The scope (layout 1.8): on-card data gathering, like a PMAC's gather buffer.
 *
 * Channels: scope_config.n_channels (1..MC_SCOPE_CHANNELS) sources, each a signal of an axis,
 * a group or the card: MC_SCOPE_SOURCE(MC_SIG_*, index), index = the axis (axis signals), the
 * group (group signals) or 0 (card signals). A sample is the value of every channel at one
 * servo tick, as binary64: exactly the values the card publishes in the status blocks of that
 * tick (a count or a word as its exact f64), taken after the tick's status is published.
 * Divider: a sample every scope_config.divider ticks (1: every tick, up to the 20 kHz servo
 * rate), counted from the arm.
 *
 * MC_OP_SCOPE_CONFIGURE validates scope_config and copies it (refused while the scope is
 * armed: MC_NACK_SCOPE_STATE). MC_OP_SCOPE_ARM starts sampling into the pre-trigger history
 * (up to pre_trigger samples, the newest kept) and waits for the trigger, evaluated on every
 * sample:
 * - MC_SCOPE_TRIG_IMMEDIATE: the first sample after the arm;
 * - MC_SCOPE_TRIG_COMMAND: the first sample after an MC_OP_SCOPE_TRIGGER (which also forces
 *   the trigger of any other kind while the scope waits);
 * - MC_SCOPE_TRIG_LEVEL: channel trigger_channel crosses level between two samples: rising
 *   (previous < level <= this one), falling (previous > level >= this one), or either;
 * - MC_SCOPE_TRIG_INPUT: debounced input trigger_input (card.inputs) changes between two
 *   samples to active (rising), inactive (falling) or either;
 * - MC_SCOPE_TRIG_FAULT: a safety fault bit (MC_FAULT_* 8..31) of any axis is set that was not
 *   at the previous sample (a latched fault present at the arm does not trigger).
 * At the trigger the card puts the history in the scope ring (oldest first; fewer than
 * pre_trigger samples if the trigger came sooner), then the trigger sample and the samples
 * after it: MC_SCOPE_ONE_SHOT stops after post_trigger samples from the trigger sample on
 * (MC_EV_SCOPE code MC_SCOPE_EV_DONE), MC_SCOPE_CONTINUOUS goes on until MC_OP_SCOPE_STOP.
 *
 * The scope ring (card produces, host consumes; the rules of every ring in this map) holds
 * MC_SCOPE_RING_LEN samples, 204.8 ms at 20 kHz whatever the channel count: a host that does
 * not keep up loses samples, never blocks the card. A sample that finds the ring full (or the
 * ring's indices corrupt) is counted in scope_status.lost and dropped; the first loss after a
 * sample that went in posts MC_EV_SCOPE code MC_SCOPE_EV_LOST. Each entry carries its servo
 * tick, so the host sees the order and any gap (consecutive samples are `divider` ticks
 * apart). A host empties the ring (tail = head) before it arms. */
#define MC_OP_SCOPE_CONFIGURE 90u /* validate and copy scope_config (axis field ignored) */
#define MC_OP_SCOPE_ARM 91u       /* start sampling and wait for the trigger (scope idle or done) */
#define MC_OP_SCOPE_TRIGGER 92u   /* trigger at the next sample (the scope waits for a trigger) */
#define MC_OP_SCOPE_STOP 93u      /* stop sampling: the scope is idle (armed, waiting or done) */
#define MC_SCOPE_CHANNELS 16u
#define MC_SCOPE_RING_LEN 4096u        /* samples in the scope ring (a power of two) */
#define MC_SCOPE_PRETRIGGER_MAX 1024u  /* scope_config.pre_trigger: 0..MC_SCOPE_PRETRIGGER_MAX */
#define MC_SCOPE_DIVIDER_MAX 65536u    /* scope_config.divider: 1..MC_SCOPE_DIVIDER_MAX */
#define MC_SCOPE_SOURCE(signal, index) ((uint32_t)(signal) | ((uint32_t)(index) << 16))
/* Scope signals (the low 16 bits of a channel's source). Axis signals (index: the axis),
 * each the axis status's value of the tick: */
#define MC_SIG_CMD_POS 1u    /* commanded position, counts (cmd_pos) */
#define MC_SIG_CMD_VEL 2u    /* commanded velocity, counts/s (cmd_vel) */
#define MC_SIG_CMD_ACC 3u    /* commanded acceleration, counts/s^2 (cmd_acc) */
#define MC_SIG_ACT_POS 4u    /* actual position, counts (act_pos) */
#define MC_SIG_ACT_VEL 5u    /* actual velocity, filtered, counts/s (act_vel) */
#define MC_SIG_FERR 6u       /* following error, counts (ferr) */
#define MC_SIG_DAC 7u        /* DAC output, V (dac_v) */
#define MC_SIG_U_REQUEST 8u  /* the servo law's output before the DAC clamp, V (u_request) */
#define MC_SIG_ENCODER 9u    /* the raw encoder count (encoder) */
/* The servo law's terms of the tick, V; P + I + D + FF is the output before the clamp (up to
 * rounding). FFPIV (Thinh Fig 5): P = kv kp (x_ref - x), I = kv ki integral,
 * D = -kv v_est, FF = kv kvff v_ref_est + kaff a_ref. PD+ (Yeh eq 2.12): P = kp e,
 * I = 0, D = kd (w_d - w_a), FF = kv w_d + ka alpha_d. PID+FF (layout 1.11): P = kp e,
 * I = the integrator's term, D = kd de/dt filtered, FF = kvff v_ref + kaff a_ref + friction. */
#define MC_SIG_SERVO_P 10u   /* the proportional term, V */
#define MC_SIG_SERVO_I 11u   /* the integral term, V */
#define MC_SIG_SERVO_D 12u   /* the velocity feedback (FFPIV) or derivative (PD+) term, V */
#define MC_SIG_SERVO_FF 13u  /* the feed-forward terms, V */
#define MC_SIG_GANTRY_SKEW 14u /* layout 1.10: the skew of a gantry's slave (index: the slave), counts;
                                * 0 for an axis that is no gantry's slave */
#define MC_SIG_COMP_POS 15u  /* layout 1.10: the compensated position, the motor's reference, counts
                              * (comp_pos: cmd_pos plus the pitch-error and backlash correction) */
#define MC_SIG_FILTER_IN 16u /* layout 1.11: the servo law's output, the biquad chain's input, V */
#define MC_SIG_FILTER_OUT 17u /* layout 1.11: the biquad chain's output before the DAC clamp, V
                               * (u_request; the law's output when no filter is set) */
#define MC_SIG_SERVO_FRICTION 18u /* layout 1.11: PID+FF's Coulomb friction feed-forward, V (part
                                   * of MC_SIG_SERVO_FF; 0 under the other laws) */
#define MC_SIG_FREQ_INJECT 19u /* layout 1.12: the sweep's sine of the tick on this axis, counts
                                * (MC_FREQ_REF) or V (MC_FREQ_OUTPUT); 0 with no sweep */
#define MC_SIG_FREQ_HZ 20u     /* layout 1.12: the frequency the sweep runs on this axis, Hz (0: none) */
/* Group signals (index: the group), the group status's values of the tick: */
#define MC_SIG_PATH_SPEED 32u /* tangential velocity before the filters, counts/s (feed) */
#define MC_SIG_PATH_ACC 33u   /* tangential acceleration, counts/s^2 (feed_acc) */
#define MC_SIG_PATH_POS 34u   /* distance along the active move, counts (path_pos) */
/* Card signals (index 0): */
#define MC_SIG_INPUTS 48u     /* the debounced digital inputs, bit i = input i (card.inputs) */
#define MC_SIG_OUTPUTS 49u    /* the digital outputs (card.outputs) */
#define MC_SIG_INPUTS_RAW 50u /* the inputs as sampled (card.inputs_raw) */
#define MC_SIG_AIN0 51u       /* layout 1.11: analog input 0, filtered, V (analog_status.input[0]) */
#define MC_SIG_AIN1 52u       /* analog input 1, filtered, V */
#define MC_SIG_AIN2 53u       /* analog input 2, filtered, V */
#define MC_SIG_AIN3 54u       /* analog input 3, filtered, V */
#define MC_SIG_AIN4 55u       /* analog input 4, filtered, V */
#define MC_SIG_AIN5 56u       /* analog input 5, filtered, V */
#define MC_SIG_AIN6 57u       /* analog input 6, filtered, V */
#define MC_SIG_AIN7 58u       /* analog input 7, filtered, V */
#define MC_SIG_AOUT0 59u      /* spare DAC output 0, V (analog_status.output[0]) */
#define MC_SIG_AOUT1 60u      /* spare DAC output 1, V */
#define MC_SIG_AOUT2 61u      /* spare DAC output 2, V */
#define MC_SIG_AOUT3 62u      /* spare DAC output 3, V */
#define MC_SIG_PSO 63u        /* the PSO's output, V or duty 0..1 (analog_status.pso_value) */
/* scope_config.mode */
#define MC_SCOPE_ONE_SHOT 0u       /* post_trigger samples from the trigger sample on, then done */
#define MC_SCOPE_CONTINUOUS 1u     /* until MC_OP_SCOPE_STOP */
/* scope_config.trigger */
#define MC_SCOPE_TRIG_IMMEDIATE 0u /* the first sample after the arm */
#define MC_SCOPE_TRIG_COMMAND 1u   /* the first sample after an MC_OP_SCOPE_TRIGGER */
#define MC_SCOPE_TRIG_LEVEL 2u     /* channel trigger_channel crosses level */
#define MC_SCOPE_TRIG_INPUT 3u     /* an edge of debounced input trigger_input */
#define MC_SCOPE_TRIG_FAULT 4u     /* a safety fault bit of an axis appears */
/* scope_config.edge (level and input triggers) */
#define MC_SCOPE_RISING 0u    /* previous < level <= this one; an input becoming active */
#define MC_SCOPE_FALLING 1u   /* previous > level >= this one; an input becoming inactive */
#define MC_SCOPE_EITHER 2u    /* either way */
/* scope_status.state */
#define MC_SCOPE_IDLE 0u      /* not sampling */
#define MC_SCOPE_WAITING 1u   /* armed: sampling into the history, waiting for the trigger */
#define MC_SCOPE_CAPTURING 2u /* triggered: samples go to the ring */
#define MC_SCOPE_DONE 3u      /* a one-shot capture ended */
/* MC_EV_SCOPE codes (seq: the MC_OP_SCOPE_ARM) */
#define MC_SCOPE_EV_TRIGGERED 1 /* value: the trigger sample's tick */
#define MC_SCOPE_EV_DONE 2      /* a one-shot capture ended; value: the samples it put in the ring
                                 * or lost (pre-trigger + post_trigger) */
#define MC_SCOPE_EV_LOST 3      /* a sample found the ring full; value: scope_status.lost */
#define MC_NACK_SCOPE_SIGNAL 110   /* an unknown signal, or an axis or group index the card has not */
#define MC_NACK_SCOPE_CHANNELS 111 /* n_channels 0 or above MC_SCOPE_CHANNELS */
#define MC_NACK_SCOPE_DIVIDER 112  /* a divider 0 or above MC_SCOPE_DIVIDER_MAX */
#define MC_NACK_SCOPE_TRIGGER 113  /* an unknown mode, trigger kind or edge, a trigger channel
                                    * >= n_channels, a trigger input >= MC_INPUTS, a level not
                                    * finite, or a one-shot with post_trigger 0 */
#define MC_NACK_SCOPE_PRETRIGGER 114 /* pre_trigger above MC_SCOPE_PRETRIGGER_MAX */
#define MC_NACK_SCOPE_STATE 115    /* configure or arm while armed, trigger while not waiting,
                                    * stop while idle, arm before a configure */

/* Layout 1.8: the configuration read back. MC_OP_READ_CONFIG makes the card write the settings
 * it holds (its validated, applied copy, not what a host last wrote) into the configuration
 * block of the kind and index asked for, before its ack; the host reads the block after the ack.
 * So the card writes the host's configuration blocks in two places only: at boot (the reset
 * values) and while it serves a MC_OP_READ_CONFIG of that block. A host does not write a block
 * while its read-back is outstanding (the SDK serialises both on one lock). Reading back changes
 * nothing on the card.
 * MC_CONFIG_AXIS fills axis_config[i] (with the scale), axis_pdplus[i] (the PD+ block the
 * axis runs, all zero while its servo law is not PD+) and, layout 1.11, axis_pidff[i] (the
 * PID+FF gains, all zero while its law is not PID+FF); MC_CONFIG_GROUP fills group_config[i]
 * (naxes 0 and the rest zero: the group is not configured). */
#define MC_OP_READ_CONFIG 96u /* args: block kind (MC_CONFIG_*), index (axis or group; 0 for the
                               * card-wide blocks). A kind the card does not know, or an argument
                               * that is not an integer: MC_NACK_CONFIG_KIND; an axis beyond
                               * identity.num_axes: MC_NACK_BAD_AXIS; a group beyond
                               * MC_MAX_GROUPS: MC_NACK_BAD_GROUP */
#define MC_OP_SET_SCALE 97u   /* axis: the axis. args: counts per user unit (|scale| in
                               * MC_SCALE_MIN..MC_SCALE_MAX, negative: the user's axis runs against
                               * the encoder; else MC_NACK_OUT_OF_RANGE, NaN: MC_NACK_NOT_FINITE).
                               * Kept for hosts, read back in axis_config.scale; the card does not
                               * use it. Any state */
#define MC_CONFIG_CARD 1u         /* card_config (index 0) */
#define MC_CONFIG_AXIS 2u         /* axis_config[i], axis_pdplus[i] and axis_pidff[i] */
#define MC_CONFIG_AXIS_FILTER 3u  /* axis_filter[i] */
#define MC_CONFIG_GROUP 4u        /* group_config[i] */
#define MC_CONFIG_SAFETY 5u       /* safety (index 0) */
#define MC_CONFIG_AXIS_SAFETY 6u  /* axis_safety[i] */
#define MC_CONFIG_AXIS_HOMING 7u  /* axis_homing[i] */
#define MC_CONFIG_GROUP_PATH 8u   /* group_path[i] */
#define MC_CONFIG_IO 9u           /* io_config (index 0) */
#define MC_SCALE_MIN 1e-9         /* |counts per user unit|: a nanometre-class unit on a coarse */
#define MC_SCALE_MAX 1e12         /* encoder to a kilometre on a fine one */
#define MC_NACK_CONFIG_KIND 116   /* MC_OP_READ_CONFIG: an unknown block kind, or a kind or index
                                   * that is not an integer */

/* Layout 1.9: leadscrew pitch-error and backlash compensation, per axis. A table of points
 * (position, forward correction, reverse correction), positions strictly increasing, in the
 * axis's position frame (the homed one: the table is used only while the axis is homed,
 * MC_MOTION_HOMED, and not homing). Between points the correction is linear in the position;
 * outside the table the end point's holds. A table without MC_COMP_BIDIR has one correction per
 * point (the forward one; the reverse one must be equal). Backlash adds +backlash/2 moving
 * forward and -backlash/2 moving in reverse. The direction is that of the commanded velocity (at
 * rest: the last one). The servo follows commanded + correction, so the encoder (on the motor)
 * is driven to where the load is right; the status's act_pos is the load's position (encoder
 * position - correction) and comp_pos the motor's reference. Whenever the correction would jump
 * (a reversal, a table loaded or cleared, homed gained or lost) the jump is taken up by a ramp
 * within the table's ramp velocity and acceleration (jerk: acceleration x 1000 /s): never a step.
 * Loading: MC_OP_COMP_TABLE opens a table (0 points and 0 backlash: compensation off, at once),
 * MC_OP_COMP_DATA sends its points in order, the last one makes it the axis's; any refusal
 * leaves the table in force as it was and closes the open one. An axis that is not at rest
 * (Standstill, Disabled or ErrorStop with no motion) refuses both (MC_NACK_COMP_BUSY).
 * MC_OP_COMP_READ writes the table in force into comp_readback (MC_COMP_READ_MAX points from a
 * first index) before its ack. */
#define MC_OP_COMP_TABLE 98u  /* axis: the axis. args: points (0..MC_COMP_MAX_POINTS), bound (the
                               * largest |correction + backlash/2| allowed, counts, > 0), backlash
                               * (counts, >= 0), ramp velocity (counts/s), ramp acceleration
                               * (counts/s^2) (both in the kinematic limit range). flags:
                               * MC_COMP_BIDIR. A bad count, bound, backlash, ramp or flags:
                               * MC_NACK_COMP_TABLE */
#define MC_OP_COMP_DATA 99u   /* axis: the axis. args: index of the first point, count
                               * (1..MC_COMP_DATA_MAX), then position, forward correction, reverse
                               * correction of each (counts). Every argument finite (else
                               * MC_NACK_NOT_FINITE); no open table or out of order:
                               * MC_NACK_COMP_SEQUENCE; positions not strictly increasing:
                               * MC_NACK_COMP_ORDER; a correction beyond the bound (with half the
                               * backlash), or reverse != forward without MC_COMP_BIDIR:
                               * MC_NACK_COMP_BOUND */
#define MC_OP_COMP_READ 100u  /* axis: the axis. args: index of the first point (0..MC_COMP_MAX_POINTS).
                               * Any state; taken without a session (it reads) */
#define MC_COMP_MAX_POINTS 256u
#define MC_COMP_DATA_MAX 4u
#define MC_COMP_READ_MAX 32u
#define MC_COMP_BIDIR (1u << 0) /* the table gives a correction per direction */
#define MC_NACK_COMP_TABLE 120  /* compensation: a point count, bound, backlash, ramp or flags out
                                 * of range */
#define MC_NACK_COMP_SEQUENCE 121 /* compensation data without an open table, or out of order */
#define MC_NACK_COMP_ORDER 122  /* compensation positions not strictly increasing */
#define MC_NACK_COMP_BOUND 123  /* a correction beyond the table's bound */
#define MC_NACK_COMP_BUSY 124   /* the axis is not at rest: its compensation cannot change */
#define MC_NACK_PLANE_AXES 139  /* an arc's plane of two group axes names one axis twice */

/* layout 1.10: the handwheel (MPG). An auxiliary encoder input jogs an axis: each detent of the
 * wheel (`detent` auxiliary counts, 4 for a quadrature wheel with one detent per cycle) moves the
 * axis's target by `ratio` counts (x1, x10, x100...), exactly: the target is the anchor plus
 * ratio * (aux count - anchor count) / detent, nothing summed tick by tick. The axis follows the
 * target from its commanded state along a time-optimal jerk-limited trajectory within its jog
 * limits (axis_config.jog_max_vel, jog_accel, jog_jerk; the override does not scale it), in
 * SynchronizedMotion. The target is never further ahead of the commanded position than the
 * axis's stop distance from jog_max_vel (at jog_accel, jog_jerk) plus one servo period at
 * jog_max_vel: what the wheel turns beyond that is dropped (the anchor moves), so nothing runs on
 * when the wheel stops. Once homed with soft limits on, the wheel cannot move the target beyond a
 * soft limit (the turns beyond are dropped: the axis stops at the limit, no trip). An input
 * drives one axis at a time: selecting it for another axis hands it over (the first one goes on
 * to its target as a DiscreteMotion: MC_EV_MOTION_DONE with the seq of its MC_OP_HANDWHEEL,
 * then Standstill). MC_OP_HALT, MC_OP_STOP, power off and safety stops end it as any motion, and a
 * move, jog, MC_Home or gearing on the axis is refused (MC_NACK_INVALID_STATE) while it runs. */
#define MC_OP_HANDWHEEL 104u     /* axis: the axis (not in an enabled group). args: input
                                  * (0..MC_AUX_ENCODERS-1, else MC_NACK_HANDWHEEL_INPUT), ratio
                                  * (axis counts per detent, a whole number, 1 <= |ratio| <=
                                  * MC_HANDWHEEL_RATIO_MAX; negative: the other way), detent
                                  * (auxiliary counts per detent, 1..MC_HANDWHEEL_DETENT_MAX)
                                  * (else MC_NACK_HANDWHEEL_RATIO). From Standstill, Discrete or
                                  * ContinuousMotion (Aborting: the target starts where the
                                  * axis's jog ramp stops it) or the axis's own handwheel (a new
                                  * input or ratio, from the target it has: the motion and its
                                  * seq go on). Ack value: the seq of the handwheel's motion */
#define MC_OP_HANDWHEEL_OFF 105u /* axis: the axis, whose handwheel runs (else
                                  * MC_NACK_INVALID_STATE): the axis goes on to the wheel's last
                                  * target as a DiscreteMotion, MC_EV_MOTION_DONE with the seq
                                  * of its MC_OP_HANDWHEEL, then Standstill */
#define MC_HANDWHEEL_RATIO_MAX 10000u
#define MC_HANDWHEEL_DETENT_MAX 1024u
#define MC_NACK_HANDWHEEL_INPUT 129 /* a handwheel input the card does not have (not a whole
                                     * number in 0..MC_AUX_ENCODERS-1) */
#define MC_NACK_HANDWHEEL_RATIO 130 /* a handwheel ratio that is 0, not a whole number or beyond
                                     * MC_HANDWHEEL_RATIO_MAX, or a detent outside
                                     * 1..MC_HANDWHEEL_DETENT_MAX */

/* Gantry axes (layout 1.10). A gantry is one logical axis driven by a master and 1..MC_GANTRY_MAX_SLAVES
 * slaves, each with its own servo loop and drive. Every tick each slave's reference is the master's
 * commanded reference of the same tick (position, velocity, acceleration) plus the slave's offset in
 * force (hold) on the position and the yaw loop's correction c on the acceleration (which the servo
 * law turns into drive output at once, through its acceleration feed-forward):
 *   skew e = (slave actual - master actual) - hold             (counts, sensed this tick)
 *   moving (the master's reference velocity or acceleration not 0):
 *     I += ki * (e - clamp(e, -1, 1)) * Ts;   c = -(kp * e + I)
 *   at rest: I = 0;   c = -kp * (e - clamp(e, -1, 1))          (no hunting within a count)
 *   |I|, |c| <= the slave's stop_decel;   slave reference = (m.pos + hold, m.vel, m.acc + c)
 * kp in 1/s^2, ki in 1/s^3. hold is the skew the slave had when it was coupled (so forming never
 * moves a slave), and becomes the slave's square offset once MC_OP_GANTRY_HOME has squared the bridge.
 * |e| > skew_limit while coupled stops every axis of the gantry together (category 1,
 * MC_STOP_GANTRY_SKEW; the slaves follow the master's stop ramp while they have power) and posts
 * MC_EV_GANTRY_FAULT. A safety stop of any member stops the others (category of the member's stop,
 * MC_STOP_GANTRY) and posts MC_EV_GANTRY_FAULT. While formed the slaves are driven by the gantry only
 * (SynchronizedMotion): every command naming a slave as its axis, a group member, or a geared slave is
 * refused with MC_NACK_GANTRY_SLAVE (the compensation commands and reads excepted);
 * MC_OP_POWER_ON/OFF and MC_OP_RESET of the master act on every member; MC_OP_HOME and
 * MC_OP_SET_POSITION of the master are refused with MC_NACK_GANTRY_STATE (they move the master's
 * frame: MC_OP_GANTRY_HOME homes a gantry). A group, a path, gearing or a stream that drives the
 * master drives the slaves. */
#define MC_MAX_GANTRIES 4u
#define MC_GANTRY_MAX_SLAVES 4u
#define MC_GANTRY_KP_MAX 1e9     /* kp in [0, MC_GANTRY_KP_MAX], 1/s^2 */
#define MC_GANTRY_KI_MAX 1e12    /* ki in [0, MC_GANTRY_KI_MAX], 1/s^3 */
#define MC_OP_GANTRY_FORM 108u   /* axis: the gantry (0..MC_MAX_GANTRIES-1). args: master, slaves n
                                  * (1..MC_GANTRY_MAX_SLAVES), kp (1/s^2), ki (1/s^3), skew limit (counts, > 0, in
                                  * the position range), then each slave's axis and square offset
                                  * (counts, in the position range). Every member Standstill, or every
                                  * member Disabled. A gantry index, master or slave that is no axis of
                                  * the card, a count out of range, master == slave or a slave twice:
                                  * MC_NACK_GANTRY_AXES; gains, limit or offset out of range:
                                  * MC_NACK_GANTRY_GAINS; a member in another gantry, a slave that is a
                                  * member of a configured group, a member geared, cammed or streaming:
                                  * MC_NACK_GANTRY_IN_USE; the gantry formed already, the members not
                                  * all at rest with the same power: MC_NACK_GANTRY_STATE */
#define MC_OP_GANTRY_DISSOLVE 109u /* axis: the gantry. The master at rest (Standstill, Disabled or
                                    * ErrorStop with no ramp running), else MC_NACK_GANTRY_STATE (as for a
                                    * gantry not formed); the slaves hold where they are (Standstill) */
#define MC_OP_GANTRY_HOME 110u   /* axis: the gantry. Every member Standstill (else MC_NACK_GANTRY_STATE):
                                  * each member runs its own MC_OP_HOME (its axis_homing block, home
                                  * position 0) with the coupling suspended; once all are homed, each
                                  * slave moves (within its homing block's velocity and acceleration)
                                  * until slave - master = its square offset, which becomes its hold;
                                  * then the gantry is coupled again and MC_EV_GANTRY_HOMED posts (code
                                  * 0, value: slave 0's skew). A side that fails: the others halt, the
                                  * gantry is coupled where they stand, MC_EV_GANTRY_HOMED with the
                                  * failure's MC_HOMING_ERR_* and the failing axis as value. The
                                  * members' own MC_EV_MOTION_DONE / MC_EV_HOMING_FAILED carry this seq */
#define MC_NACK_GANTRY_SLAVE 134  /* the axis is a slave of a formed gantry: it cannot be used by itself */
#define MC_NACK_GANTRY_IN_USE 135 /* a gantry member already in a gantry, a group, geared or streaming */
#define MC_NACK_GANTRY_AXES 136   /* gantry index, master or slaves out of range, master == slave, a
                                   * slave twice */
#define MC_NACK_GANTRY_GAINS 137  /* kp, ki, skew limit or square offset out of range */
#define MC_NACK_GANTRY_STATE 138  /* the gantry (or its members) not in a state that takes this */
/* gantry_status[].phase */
#define MC_GANTRY_NONE 0u      /* not formed */
#define MC_GANTRY_COUPLED 1u   /* the slaves follow the master */
#define MC_GANTRY_HOMING 2u    /* MC_OP_GANTRY_HOME: each side homes on its own */
#define MC_GANTRY_SQUARING 3u  /* MC_OP_GANTRY_HOME: the slaves move to their square offsets */

/* Group homing (layout 1.11, PLCopen Part 4 MC_GroupHome). A group homes its axes in stages: the
 * axes of a stage home together, each with its own homing (its axis_homing block, MC_OP_HOME's
 * position 0, as MC_OP_GANTRY_HOME's sides), and a stage starts once every axis of the stage
 * before it is homed and at rest. A member that is a gantry's master homes its gantry
 * (MC_OP_GANTRY_HOME, squaring included). The order is MC_OP_GROUP_HOME's, or the group's
 * configured one (group_config.home_stages, home_order[]). From GroupStandby (MC_NACK_GROUP_DISABLED
 * for a disabled group, MC_NACK_INVALID_STATE for one not at rest, MC_NACK_AXIS_BUSY for a member
 * that moves on its own); then the order, NaN or infinite: MC_NACK_NOT_FINITE, in this order: the
 * stage count (1..MC_GROUP_HOME_STAGES, else MC_NACK_BAD_CONFIG; 0 without a configured order:
 * MC_NACK_HOME_STAGE), each stage's mask (an integer 0..255; a bit beyond the group's axes:
 * MC_NACK_HOME_AXIS; 0: MC_NACK_HOME_STAGE), an axis in two stages (MC_NACK_HOME_TWICE), then
 * every axis's homing as MC_OP_HOME checks it (a gantry: MC_NACK_GANTRY_STATE). The group is in MC_GROUP_HOMING meanwhile (its members in Homing, or at rest waiting for their stage
 * or homed); once all are homed and at rest it goes to GroupStandby and MC_EV_GROUP_HOMED posts. A
 * member whose homing fails ends it as a whole: every other member still homing halts on its stop
 * ramp (stop reason MC_STOP_GROUP_HOMING), the later stages never start, and once they are at rest
 * the group goes to GroupStandby and MC_EV_GROUP_HOMING_FAILED posts with the member and its
 * MC_HOMING_ERR_*. MC_OP_GROUP_HALT and MC_OP_GROUP_STOP end it the same way (the members halt with
 * stop reason MC_STOP_HALT or MC_STOP_STOP; a stop leaves the group in GroupStopping until
 * MC_OP_GROUP_STOP_RELEASE), as does MC_OP_GROUP_DISABLE (at once: the group is disabled); a
 * member's safety stop stops the others (MC_STOP_GROUP) and the group goes to GroupErrorStop; the
 * event's code is then MC_GROUP_HOME_ABORTED. The members' own MC_EV_MOTION_DONE /
 * MC_EV_HOMING_FAILED carry the command's seq. */
#define MC_GROUP_HOME_STAGES 8u    /* the most stages of a home order */
#define MC_OP_GROUP_HOME 106u      /* MC_GroupHome. axis: the group. args: the stage count (0: the
                                    * configured order), then each stage's mask of group axes */
#define MC_GROUP_HOME_ABORTED (-1) /* MC_EV_GROUP_HOMING_FAILED's code when a halt, stop, disable or
                                    * safety stop ended it (not one of the MC_HOMING_ERR_*) */
#define MC_NACK_HOME_AXIS 131      /* a home order names an axis the group does not have */
#define MC_NACK_HOME_TWICE 132     /* a home order names an axis in two stages */
#define MC_NACK_HOME_STAGE 133     /* a home order with an empty stage (or no stages, and none
                                    * configured) */

/* Layout 1.10: rotary (modulo) axes. An axis with a modulo period m > 0 (counts) reports its
 * commanded, actual and target positions, MC_EV_MOTION_DONE's position and its probe captures
 * wrapped into [0, m); the raw encoder count is the shaft's, unwrapped. The card keeps the turn
 * count and the position within the turn apart (integers: the period is held in
 * 1/65536 count, the encoder is an integer), so the wrapped position does not
 * drift however many turns the axis makes. MC_OP_MOVE_ABSOLUTE takes a target in [0, m) (else
 * MC_NACK_MODULO_MOVE) and goes there the way its flags name (PLCopen MC_Direction; shortest
 * by default; a tie of exactly half a turn goes positive; a target where the axis is: no
 * motion); relative and additive moves go their distance, turns included. Soft limits do not
 * apply to a modulo axis (they are kept, and hold again once the axis is linear). */
#define MC_OP_SET_MODULO 101u  /* axis: the axis. args: the period, counts (0: linear; else
                                * MC_MODULO_MIN..MC_MODULO_MAX, rounded to 1/65536
                                * count; NaN or infinite: MC_NACK_NOT_FINITE; out of range:
                                * MC_NACK_MODULO_RANGE). Only at rest (Standstill with no motion,
                                * Disabled, or ErrorStop with no motion; else MC_NACK_MODULO_BUSY).
                                * An armed compare channel watching the axis: MC_NACK_COMPARE_TURN
                                * (layout 1.13). The positions are wrapped at once. Read back in
                                * axis_config.modulo */
#define MC_MODULO_MIN 1.0          /* the smallest period, counts */
#define MC_MODULO_MAX 1e11         /* the largest period, counts (a position within the turn
                                    * times 65536 stays exact in a double) */
#define MC_MOVE_DIR_SHIFT 14u      /* 2 bits of MC_OP_MOVE_ABSOLUTE's flags (PLCopen MC_Direction): */
#define MC_MOVE_DIR_SHORTEST 0u    /*   the shorter way round (the default) */
#define MC_MOVE_DIR_POSITIVE 1u    /*   positive: up to a turn less a count forward */
#define MC_MOVE_DIR_NEGATIVE 2u    /*   negative */
#define MC_MOVE_DIR_CURRENT 3u     /*   the direction of the motion in progress, else of the last one
                                    *   (positive if the axis never moved) */
#define MC_NACK_MODULO_RANGE 125   /* a modulo period below MC_MODULO_MIN or above MC_MODULO_MAX,
                                    * or negative */
#define MC_NACK_MODULO_BUSY 126    /* the axis is not at rest: its period cannot change */
#define MC_NACK_MODULO_MOVE 127    /* an absolute move that does not fit the axis: on a modulo axis
                                    * a target not in 0 <= target < modulo, on a linear axis a
                                    * direction other than MC_MOVE_DIR_SHORTEST */

/* Layout 1.11: biquad filters on the servo output. Up to MC_BIQUADS filters per axis run in
 * series on the servo law's output, before the DAC clamp (filter slot 0 first). Each is a
 * second-order section discretised at the servo rate by the bilinear transform with
 * pre-warping, designed by the card from its kind and parameters; the card checks it when it
 * is set (frequencies 0 < f < servo_rate_hz / 2, the poles inside the unit circle by at least
 * MC_BIQUAD_POLE_MARGIN) and refuses it changing nothing. A filter set or cleared starts from
 * the steady state of the output of the tick (no step at rest when its DC gain is 1). What each
 * axis holds is read back in servo_filters[axis], written by the card at boot and before the
 * ack of each set or clear. A change of servo rate redesigns every filter at the new rate
 * (MC_OP_APPLY_CARD_CONFIG refuses a rate at which one would not pass these checks:
 * MC_NACK_FILTER_FREQ or MC_NACK_FILTER_UNSTABLE). Any axis state. */
#define MC_BIQUADS 4u              /* filters per axis */
#define MC_BIQUAD_NONE 0u          /* the slot is empty */
#define MC_BIQUAD_NOTCH 1u         /* freq_hz: centre; damping: the poles' damping ratio (the width:
                                    * the -3 dB band is about 2 damping freq_hz wide); depth_db: the
                                    * gain at the centre, dB (-120..0) */
#define MC_BIQUAD_LOWPASS 2u       /* second order: freq_hz: corner; damping: damping ratio
                                    * (0.707: Butterworth) */
#define MC_BIQUAD_LEAD_LAG 3u      /* first order (1 + s/w1) / (1 + s/w2): freq_hz: the zero's
                                    * w1/2pi; freq2_hz: the pole's w2/2pi (above freq_hz: a lead,
                                    * below: a lag); DC gain 1 */
#define MC_BIQUAD_RAW 4u           /* the coefficients as given: y = b0 x + b1 x[-1] + b2 x[-2]
                                    * - a1 y[-1] - a2 y[-2] */
#define MC_BIQUAD_POLE_MARGIN 1e-6 /* a filter's poles lie within 1 - margin of the origin */
#define MC_BIQUAD_RAW_B_MAX 1e6    /* a raw filter's |b0|, |b1|, |b2| at most this */
#define MC_OP_SERVO_FILTER_SET 112u /* axis: the axis. args: slot (0..MC_BIQUADS-1), kind
                                     * (MC_BIQUAD_NOTCH.._RAW), freq_hz, damping, depth_db,
                                     * freq2_hz, b0, b1, b2, a1, a2 (the arguments a kind does not
                                     * use: 0). A slot or kind out of range or not an integer:
                                     * MC_NACK_FILTER_KIND; a number not finite:
                                     * MC_NACK_NOT_FINITE; a frequency <= 0 or >= servo_rate_hz / 2:
                                     * MC_NACK_FILTER_FREQ; a damping <= 0 or above 10, a depth
                                     * out of -120..0, a raw |b| above MC_BIQUAD_RAW_B_MAX:
                                     * MC_NACK_FILTER_PARAM; the poles not inside
                                     * the unit circle by MC_BIQUAD_POLE_MARGIN:
                                     * MC_NACK_FILTER_UNSTABLE */
#define MC_OP_SERVO_FILTER_CLEAR 113u /* axis: the axis. args: slot (0..MC_BIQUADS-1, else
                                       * MC_NACK_FILTER_KIND); clearing an empty slot is not an
                                       * error */
#define MC_NACK_FILTER_KIND 140     /* a filter slot or kind out of range or not an integer */
#define MC_NACK_FILTER_FREQ 141     /* a filter frequency not above 0 and below the Nyquist
                                     * frequency (servo_rate_hz / 2) */
#define MC_NACK_FILTER_PARAM 142    /* a filter's damping (0 < damping <= 10), depth
                                     * (-120 <= depth_db <= 0) or raw b (|b| <= MC_BIQUAD_RAW_B_MAX)
                                     * out of range */
#define MC_NACK_FILTER_UNSTABLE 143 /* the filter's poles are not inside the unit circle by
                                     * MC_BIQUAD_POLE_MARGIN */
#define MC_NACK_PIDFF_GAINS 144     /* MC_OP_APPLY_AXIS_CONFIG with MC_SERVO_PIDFF: a gain
                                     * negative, a derivative cut-off or a friction deadband not
                                     * above 0 (not finite: MC_NACK_NOT_FINITE) */
/* Layout 1.11: analog I/O and the path-speed output (PSO).
 *
 * Analog inputs: MC_ANALOG_INPUTS inputs, each sampled every servo tick by a 16-bit bipolar ADC
 * of +-MC_ANALOG_RANGE V: code = round(v / MC_ADC_LSB) saturated to -32768..32767, the sample
 * code * MC_ADC_LSB (MC_ADC_LSB = 20 V / 65536, about 0.305 mV; the top code is 10 V - 1 LSB).
 * Each input has a first-order low-pass filter: y += alpha * (sample - y) every tick, alpha =
 * 1 - exp(-2 pi fc / servo rate) (at the sample instants the step response of the continuous
 * filter with cut-off fc, exactly); fc 0: no filter (y = the sample). The filter starts from 0 V
 * at boot and keeps its value when its cut-off changes. The threshold: an input is above once
 * y >= threshold, and below again once y <= threshold - hysteresis (hysteresis >= 0); the state
 * is recomputed from y, with no event, when the input is configured. A change of state posts
 * MC_EV_ANALOG when the input's MC_ANALOG_EV_RISE / _FALL flag asks for it. analog_status holds
 * each input's sample, filtered value, state and configuration of the last tick.
 *
 * Spare DAC outputs: MC_ANALOG_OUTPUTS outputs, the axes' 12-bit +-10 V DAC (an LSB of 20/4096 V,
 * codes 0..4095: -10 V .. 10 V - 1 LSB). MC_OP_ANALOG_OUTPUT sets one; the volts are clamped to
 * that range and quantised; analog_status.output reads back what the DAC puts out. 0 V at boot.
 *
 * The path-speed output (PSO; laser power, a dispenser): one per card, on a group. Every tick,
 * after the group's path step, the card takes the group's ACTUAL tangential speed
 * v = sqrt(sum of w_i^2 over the group's axes) (counts/s), w_i axis i's velocity estimate of
 * the tick (act_vel) through the PSO's own first-order low-pass filter of cut-off filter_hz
 * (w_i += beta * (act_vel_i - w_i), beta = 1 - exp(-2 pi filter_hz / servo rate); filter_hz 0:
 * w_i = act_vel_i; the filter smooths the encoder's one-count steps, and lags by about
 * 1 / (2 pi filter_hz)), and, while the gate output's bit is set in
 * card.outputs (the host's and the path's outputs, MC_OP_PATH_OUTPUT: G-code M62..M65), drives
 *     value = clamp(min + (max - min) * v / v_ref, min, max)
 * on its output: a spare DAC (volts, quantised as MC_OP_ANALOG_OUTPUT's), or with MC_PSO_PWM a
 * PWM on a digital output (value: the duty cycle 0..1 at pwm_hz; the output's bit in
 * card.outputs reads 1 while the duty is above 0). With the gate closed the output is 0 (0 V, or
 * duty 0). v_ref is the speed of full output, e.g. the program's feed: through a corner the
 * output follows the feed the axes actually make. analog_status holds the PSO's state, speed
 * and value of the tick. */
#define MC_ANALOG_INPUTS 8u
#define MC_ANALOG_OUTPUTS 4u
#define MC_ANALOG_RANGE 10.0       /* the ADC's and the DACs' range, +-V */
#define MC_ADC_LSB 0.00030517578125 /* the ADC's step, V: 20 / 65536 */
#define MC_PSO_PWM_HZ_MAX 100000.0 /* the highest PWM frequency, Hz */
#define MC_OP_ANALOG_INPUT 116u    /* args: input (0..MC_ANALOG_INPUTS-1), cutoff_hz (0: no filter;
                                    * else > 0 and at most half the servo rate), threshold (V, within
                                    * +-MC_ANALOG_RANGE), hysteresis (V, 0..2 * MC_ANALOG_RANGE).
                                    * flags: MC_ANALOG_EV_RISE, MC_ANALOG_EV_FALL. axis field ignored */
#define MC_OP_ANALOG_OUTPUT 117u   /* args: output (0..MC_ANALOG_OUTPUTS-1), volts (clamped to the DAC's
                                    * range; NaN: MC_NACK_NOT_FINITE). An output the PSO drives:
                                    * MC_NACK_ANALOG_CHANNEL. axis field ignored */
#define MC_OP_PSO 118u             /* axis: the group (configured, else MC_NACK_PSO_GROUP). args: output
                                    * (a spare DAC 0..MC_ANALOG_OUTPUTS-1, or with MC_PSO_PWM a digital
                                    * output 0..MC_OUTPUTS-1 no compare channel pulses), gate (a digital
                                    * output 0..MC_OUTPUTS-1, not the PWM's), min, max (min <= max; V
                                    * within the DAC's range, or a duty 0..1), v_ref (counts/s, > 0),
                                    * pwm_hz (MC_PSO_PWM: 1..MC_PSO_PWM_HZ_MAX; else ignored), filter_hz
                                    * (0: none; else > 0 and at most half the servo rate). flags:
                                    * MC_PSO_PWM. Anything else out of range: MC_NACK_PSO_CONFIG. Replaces
                                    * a PSO running (its old output goes to 0 first) */
#define MC_OP_PSO_OFF 119u         /* the PSO stops; its output goes to 0 (0 V, or duty 0). Accepted when
                                    * it is off. axis field ignored */
#define MC_ANALOG_EV_RISE (1u << 0) /* MC_OP_ANALOG_INPUT flags: MC_EV_ANALOG when the input goes above */
#define MC_ANALOG_EV_FALL (1u << 1) /* ... and when it goes below again */
#define MC_PSO_PWM (1u << 0)        /* MC_OP_PSO flags: a PWM on a digital output (else a spare DAC) */
/* analog_status.pso_state */
#define MC_PSO_OFF 0u              /* not configured */
#define MC_PSO_CLOSED 1u           /* configured, the gate output off: the output is 0 */
#define MC_PSO_ON 2u               /* the gate output on: the output follows the speed */
#define MC_NACK_ANALOG_CHANNEL 145 /* an analog input or output the card does not have (not a whole
                                    * number below MC_ANALOG_INPUTS / MC_ANALOG_OUTPUTS), or a spare
                                    * DAC the PSO drives */
#define MC_NACK_ANALOG_FILTER 146  /* a cut-off below 0 or above half the servo rate (Nyquist) */
#define MC_NACK_ANALOG_THRESHOLD 147 /* a threshold beyond +-MC_ANALOG_RANGE, a hysteresis below 0 or
                                      * above 2 * MC_ANALOG_RANGE, or unknown flags */
#define MC_NACK_PSO_CONFIG 148     /* a PSO output, gate, range (min > max, beyond the DAC's range or a
                                    * duty beyond 0..1), v_ref (<= 0), PWM frequency or filter (below 0,
                                    * above half the servo rate) out of range, the gate equal to the
                                    * PWM output, a PWM output a compare channel pulses, or unknown
                                    * flags */
#define MC_NACK_PSO_GROUP 149      /* a PSO on a group that does not exist (index beyond MC_MAX_GROUPS)
                                    * or is not configured */
#define MC_NACK_TICK_PASSED 160   /* MC_OP_AT_TICK for a tick the card has run (layout 1.12) */
#define MC_NACK_TIMED_FULL 161    /* MC_TIMED_SLOTS timed commands are held already */
#define MC_NACK_TIMED_ALONE 162   /* MC_OP_AT_TICK without a command published with it, or timing a
                                   * command that cannot be timed (MC_OP_AT_TICK, the session and
                                   * commit opcodes, the pieces of
                                   * MC_OP_GROUP_MOVE_CIRCULAR_NORMAL) */
#define MC_NACK_TICK_FAR 163      /* a tick more than MC_TIMED_MAX_AHEAD ticks ahead, or a key or
                                   * tick that is not a whole number in range */
#define MC_NACK_COMMIT_LATE 164   /* MC_OP_SYNC_COMMIT on or after its tick: nothing of the key runs */
#define MC_NACK_NOT_MASTER 165    /* MC_OP_SYNC_COMMIT on a follower: commit on the bus's master */
#define MC_NACK_NOT_COMMITTED 166 /* a timed command whose key's commit was not seen by its tick */
#define MC_NACK_SYNC_LOST 167     /* a timed command dropped: the card lost the bus's master */
#define MC_NACK_TIMED_REFUSED 168 /* the command of a refused MC_OP_AT_TICK: not executed */
#define MC_NACK_CANCELLED 169     /* a held timed command dropped (MC_OP_TIMED_CANCEL, a detach) */

/* Layout 1.12: path arcs in a plane given by a normal vector (three group axes a, b, c; the
 * other group axes move linearly with the arc length: a helix). The plane is the group's until
 * it is set again or the group is configured again: MC_OP_PATH_ARC_PLANE sets it, each
 * MC_OP_PATH_ARC_NORMAL runs an arc in it. The arc turns counter-clockwise about the normal
 * (the right-hand rule: the normal reversed, the arc runs the other way) in the plane through
 * the path's end with that normal, around the centre, from the start to the end (an end at the
 * start: a full turn), as APT's CIRCLE/ record (centre, axis, then the end). The centre must lie
 * in that plane and the end on the circle, each within the group's tolerance
 * (group_config.tolerance: MC_NACK_ARC_OFF_PLANE, MC_NACK_CENTRE_NOT_EQUIDISTANT; the end is then
 * put exactly on the circle); the end lies in the plane too unless MC_ARC_RISE allows it off
 * along the normal (the rise of a helix along the normal, as G17's Z). On the path it is treated
 * as an arc: its blends, look-ahead and every axis's limits, the plane's components of its
 * tangent and curvature on each of the three axes. A zero radius: MC_NACK_ZERO_LENGTH_ARC. */
#define MC_OP_PATH_ARC_PLANE 124u    /* args: a, b, c (three distinct group axes, else MC_NACK_ARC_AXES;
                                      * beyond the group: MC_NACK_AXIS_NOT_IN_GROUP), n_a, n_b, n_c
                                      * (the normal, any length but not 0: MC_NACK_ARC_NORMAL; NaN:
                                      * MC_NACK_NOT_FINITE). The group's normal plane for the
                                      * following MC_OP_PATH_ARC_NORMAL (configured group) */
#define MC_OP_PATH_ARC_NORMAL 125u   /* args: id, feed, tolerance (as MC_OP_PATH_LINE), centre_a,
                                      * centre_b, centre_c, end_a, end_b, end_c, then the targets of
                                      * the other group axes in order (a helix). flags:
                                      * MC_MOVE_RELATIVE (the centre, end and targets from the
                                      * path's end), MC_CIRC_HELIX_RELATIVE (the other axes'
                                      * targets are distances), MC_ARC_RISE, MC_PATH_*. No plane
                                      * set: MC_NACK_ARC_NORMAL */
#define MC_ARC_RISE (1u << 2)        /* MC_OP_PATH_ARC_NORMAL (layout 1.13: and
                                      * MC_OP_GROUP_MOVE_CIRCULAR_NORMAL): the end may lie off the
                                      * plane along the normal (a helix along it) */
#define MC_NACK_ARC_NORMAL 156       /* a normal-vector arc's normal is zero, or no plane was set
                                      * (MC_OP_PATH_ARC_PLANE) before it */
#define MC_NACK_ARC_AXES 157         /* a normal-vector arc's plane names a group axis twice (or an
                                      * axis index that is not a whole number) */
#define MC_NACK_ARC_OFF_PLANE 158    /* a normal-vector arc's centre, or its end (without MC_ARC_RISE),
                                      * is off the plane through the start by more than the group's
                                      * tolerance */

/* Layout 1.13: MC_MoveCircular in a plane given by a normal vector, in the group's move queue:
 * a rest-to-rest S-curve of the path length along the arc within v, a, d, j (the limits along
 * the path, as MC_OP_GROUP_MOVE_CIRCULAR's; the other group axes move linearly with the arc
 * length: a helix). Its arguments take two command entries, published together (one head
 * update): MC_OP_GROUP_MOVE_CIRCULAR_NORMAL, then MC_OP_GROUP_CIRCULAR_PLANE to the same group
 * right after it. The card takes the pair as one move, answers each entry (the same outcome;
 * the move's seq is the first entry's) and refuses a piece alone or out of order with
 * MC_NACK_ARC_PIECE: the first entry with no MC_OP_GROUP_CIRCULAR_PLANE of its group after it
 * (that entry then stays in the ring, served on its own), the second without the first just
 * before it. Neither can be timed (MC_OP_AT_TICK: MC_NACK_TIMED_ALONE). The plane travels
 * with the move, not from MC_OP_PATH_ARC_PLANE: a queued move is fixed when it is taken. The
 * geometry is MC_OP_PATH_ARC_NORMAL's (above: counter-clockwise about the normal in the plane
 * through the start, the centre in it and the end on the circle within the group's tolerance,
 * then made exact; MC_ARC_RISE; an end at the start: a full turn) and each of `turns` adds a
 * full turn. A group with MC_INTERP_REFERENCE_WORD runs it exactly at its constant feed. */
#define MC_OP_GROUP_MOVE_CIRCULAR_NORMAL 129u /* args: v, a, d, j, centre_a, centre_b, centre_c,
                                               * end_a, end_b, end_c (on the plane's axes),
                                               * turns (whole, >= 0: MC_NACK_OUT_OF_RANGE).
                                               * flags: MC_MOVE_RELATIVE, MC_MOVE_BUFFERED,
                                               * the feed type, MC_ARC_RISE,
                                               * MC_CIRC_HELIX_RELATIVE */
#define MC_OP_GROUP_CIRCULAR_PLANE 131u /* the second entry of MC_OP_GROUP_MOVE_CIRCULAR_NORMAL:
                                         * args: a, b, c (three distinct group axes, else
                                         * MC_NACK_ARC_AXES; beyond the group:
                                         * MC_NACK_AXIS_NOT_IN_GROUP), n_a, n_b, n_c (the normal,
                                         * not 0: MC_NACK_ARC_NORMAL), then the targets of the
                                         * other group axes in group order (a helix) */
#define MC_NACK_ARC_PIECE 155 /* a piece of MC_OP_GROUP_MOVE_CIRCULAR_NORMAL alone or out of
                               * order: its two entries go together, the move first */

/* Layout 1.14: paths across cards. A path whose axes live on several cards of one sync bus runs
 * as one: every card holds the same segments of all the path's axes (its dimensions), plans the
 * same speed profile from them (identical firmware, identical inputs, the same ticks) and drives
 * only the dimensions that are its own group's axes. group_dims[g] names the dimensions: ndims
 * (0: the group's path is its members', as before; else 1..MC_PATH_MAX_DIMS), and for each
 * dimension the group axis it drives here or MC_DIM_REMOTE (an axis another card drives), its
 * limits (they replace group_path's per-axis limits; group_path's lookahead, low_water, accel,
 * jerk and plan_period still apply) and, for a remote one, where it starts. Every group axis
 * is exactly one dimension (else MC_NACK_PATH_DIMS). MC_OP_APPLY_GROUP_DIMS takes the block with
 * the group configured, its path idle and nothing staged (else MC_NACK_PATH_BUSY); the path then
 * starts afresh: at the group's position on its own dimensions and at `start` on the others.
 *
 * With dimensions, path segments are staged, not run: a line (MC_OP_PATH_LINE), an arc or helix
 * (MC_OP_PATH_ARC: its plane two of dimensions 0..7, its helix the other dimensions in order)
 * or a dwell is checked as it is taken (relative targets from the end of what is staged) and
 * waits, in order, up to MC_PATH_STAGE_LEN of them. A segment of more dimensions than its entry
 * holds (a line past 8, an arc past 8) continues in MC_OP_PATH_MORE, the next entry of the
 * same group, published with it (one head update): the two are taken as one segment and each is
 * answered with its outcome; either one alone or out of order is MC_NACK_PATH_MORE. A NURBS
 * segment, a normal-vector arc, an output action and MC_PATH_ABORTING are refused with
 * dimensions (MC_NACK_INCOMPATIBLE_MODE, MC_PATH_ABORTING: MC_NACK_PATH_MODE).
 * MC_OP_PATH_RELEASE moves the oldest `count` staged segments into the path, where they run as
 * any segment does (their events carry the seqs of their MC_OP_PATH_LINE/_ARC/_DWELL). Timed to
 * one tick on every card (MC_OP_AT_TICK under one committed key), the release leaves every card
 * with the same segments queued on every tick: the look-ahead plans from what is queued, so the
 * cards' profiles are the same to the last bit, and so is the motion of each dimension. A hold
 * (MC_OP_SET_OVERRIDE), pause or halt is timed the same way. A halt, stop, fault or disable
 * aborts what is staged as it aborts the path (one MC_EV_GROUP_MOTION_ABORTED per segment). */
#define MC_PATH_MAX_DIMS 16u   /* dimensions of a path across cards */
#define MC_PATH_STAGE_LEN 256u /* segments a group stages before they are released */
#define MC_DIM_REMOTE (-1)     /* group_dims.axis[]: a dimension another card drives */
#define MC_OP_APPLY_GROUP_DIMS 132u /* copy and validate group_dims[group] (above) */
#define MC_OP_PATH_MORE 133u   /* args: the targets of the segment's dimensions past those its own
                                * entry holds, in order (a line: dimensions 8..; an arc: the
                                * helix's dimensions after its first 6). Only right after the
                                * segment's entry of the same group (above) */
#define MC_OP_PATH_RELEASE 134u /* args: count (a whole number 1..path_staged, else
                                 * MC_NACK_PATH_RELEASE; more than the path has room for:
                                 * MC_NACK_QUEUE_FULL). Nothing released on a refusal */
#define MC_NACK_PATH_DIMS 170  /* group_dims: ndims over MC_PATH_MAX_DIMS, an axis[] that is not a
                                * group axis or MC_DIM_REMOTE, a group axis named twice or not at
                                * all, a group not configured; or a staging command on a group
                                * without dimensions (MC_OP_PATH_MORE, MC_OP_PATH_RELEASE) */
#define MC_NACK_PATH_MORE 171  /* a segment of more dimensions than its entry holds without its
                                * MC_OP_PATH_MORE right after it, or an MC_OP_PATH_MORE alone */
#define MC_NACK_PATH_RELEASE 172 /* MC_OP_PATH_RELEASE of more segments than are staged (or 0),
                                  * or with the group moved off where the staged segments start */

/* Layout 1.12: the frequency response measured on the card (a stepped sine). One sweep at a
 * time, on one axis enabled and at rest (Standstill, holding its position). At each of
 * `points` frequencies spaced logarithmically from from_hz to to_hz the card adds the sine
 * d[k] = amplitude sin(2 pi f k / servo_rate_hz) either to the servo's position reference
 * (MC_FREQ_REF: counts; the reference's velocity and acceleration, so the feed-forward, do not
 * see it; the closed loop) or to the servo output after the filters, before the DAC clamp
 * (MC_FREQ_OUTPUT: volts; the plant and the open loop, the loop stays closed). Each point runs
 * a whole number of measurement windows: settle windows first, then one measured; a window is
 * M ticks holding exactly `cycles` periods (at least MC_FREQ_WINDOW_MIN ticks: more periods
 * where the frequency is high), so the frequency actually run is cycles servo_rate_hz / M
 * (point[].hz) and a point starts and ends at phase 0 (the sine is continuous from point to
 * point; the sweep's first window ramps the amplitude up from 0). Over the measured window the card correlates, at the servo rate, the injected sine d,
 * the encoder position x (counts, less the position held) and the DAC output u (volts): for a
 * signal y, re = (2/M) sum y[k] cos(w k), im = -(2/M) sum y[k] sin(w k), k = 0..M-1 from the
 * window's start (a single-bin DFT over whole periods: a constant and the harmonics fall out
 * exactly). Ratios of these are the responses: closed loop T = X/D, plant P = X/U (encoder
 * counts per volt), open loop under MC_FREQ_OUTPUT L = (D - U)/U. freq_status.done counts the
 * points measured, each written whole before the count. The sweep ends with MC_EV_FREQ_DONE.
 * While it runs the axis stays in Standstill: a move, velocity, jog, home, set-position,
 * handwheel, modulo or compensation command on it is refused (MC_NACK_FREQ_BUSY); a halt,
 * stop, power-off or reset on it, an MC_OP_FREQ_STOP, and the axis leaving Standstill (a safety
 * stop, a group or coupling taking it) end the sweep at once (MC_FREQ_ABORTED; the sine is
 * removed in that tick). The following error during a sweep is the injected reference's. */
#define MC_FREQ_POINTS_MAX 256u    /* points per sweep */
#define MC_FREQ_WINDOW_MIN 1000u   /* a measurement window's least length, ticks */
#define MC_FREQ_CYCLES_MAX 1000u   /* measured periods per window at most */
#define MC_FREQ_SETTLE_MAX 60.0    /* settle_s at most, s */
#define MC_FREQ_MIN_HZ 0.1         /* the lowest frequency, Hz */
#define MC_FREQ_REF 0u             /* mode: the sine on the position reference (counts) */
#define MC_FREQ_OUTPUT 1u          /* mode: the sine on the servo output (volts) */
/* freq_status.state */
#define MC_FREQ_IDLE 0u            /* no sweep since boot */
#define MC_FREQ_RUNNING 1u         /* measuring: done points of points so far */
#define MC_FREQ_DONE 2u            /* every point measured */
#define MC_FREQ_ABORTED 3u         /* ended early: done points measured */
#define MC_OP_FREQ_START 121u      /* axis: the axis. args: mode (MC_FREQ_REF or MC_FREQ_OUTPUT), from_hz,
                                    * to_hz, points (1..MC_FREQ_POINTS_MAX), amplitude (counts, or
                                    * volts), cycles (periods measured per point, 1..MC_FREQ_CYCLES_MAX),
                                    * settle_s (0..MC_FREQ_SETTLE_MAX: settle windows before each
                                    * measured one, at least one). A number not finite:
                                    * MC_NACK_NOT_FINITE; a mode, count or frequency out of range
                                    * (MC_FREQ_MIN_HZ <= from_hz <= to_hz <= servo_rate_hz / 4):
                                    * MC_NACK_FREQ_RANGE; an amplitude <= 0, or above dac_limit_v
                                    * (MC_FREQ_OUTPUT): MC_NACK_FREQ_AMPLITUDE; MC_FREQ_REF with a sine
                                    * beyond the axis's limits (amplitude 2 pi to_hz above
                                    * axis_safety.max_velocity, amplitude (2 pi to_hz)^2 above the
                                    * card's acceleration range, 2 amplitude above min_ferror, the
                                    * position held +- amplitude beyond the soft limits in force):
                                    * MC_NACK_FREQ_LIMITS; a sweep running (any axis):
                                    * MC_NACK_FREQ_BUSY; the axis disabled: MC_NACK_AXIS_DISABLED;
                                    * not at rest in Standstill: MC_NACK_INVALID_STATE */
#define MC_OP_FREQ_STOP 122u       /* axis ignored: the sweep running ends (MC_FREQ_ABORTED,
                                    * MC_EV_FREQ_DONE); none running: accepted, nothing changes */
#define MC_NACK_FREQ_RANGE 150     /* a sweep's mode, points, cycles, settle time or frequencies
                                    * out of range (from_hz below MC_FREQ_MIN_HZ or above to_hz,
                                    * to_hz above a quarter of the servo rate) */
#define MC_NACK_FREQ_AMPLITUDE 151 /* a sweep's amplitude not above 0, or above the axis's DAC
                                    * limit for MC_FREQ_OUTPUT */
#define MC_NACK_FREQ_LIMITS 152    /* the sweep's sine would break the axis's velocity or
                                    * acceleration limits, its following error limit at rest or
                                    * its soft limits */
#define MC_NACK_FREQ_BUSY 153      /* a sweep is running: another, or that axis's motion, refused */
#define MC_NACK_PSO_OUTPUT 154     /* MC_OP_COMPARE_ARM on the digital output the PSO's PWM holds
                                    * (layout 1.12): refused, nothing changed (the other way, a PSO's
                                    * PWM on an output a compare channel pulses, is
                                    * MC_NACK_PSO_CONFIG) */
#define MC_NACK_COMPARE_TURN 159   /* layout 1.13, compare on a modulo axis: a position, series
                                    * start or table position outside 0 <= p < modulo, a series
                                    * longer than a turn ((count - 1) * pitch >= modulo; with
                                    * MC_CMP_EACH_TURN count * pitch > modulo, or count 0 with a
                                    * pitch over the turn), MC_CMP_EACH_TURN on a linear axis,
                                    * or MC_OP_SET_MODULO on an axis an armed compare channel
                                    * watches. Refused, nothing changed */

/* Event kinds (mc_event.kind) */
#define MC_EV_ACK 1u             /* the command with this seq was accepted */
#define MC_EV_NACK 2u            /* the command with this seq was refused. code: MC_NACK_* */
#define MC_EV_MOTION_DONE 3u     /* value: final actual position */
#define MC_EV_STATE_CHANGED 4u   /* code: new state, value: old state */
#define MC_EV_FAULT 5u           /* code: fault bit, value: a measurement */
#define MC_EV_MOTION_ABORTED 6u  /* code: reason (a command opcode or fault bit) */
#define MC_EV_GROUP_MOTION_DONE 8u    /* axis: group; seq: the move; value: 1 when the group is at rest in position */
#define MC_EV_GROUP_STATE_CHANGED 9u  /* axis: group; code: new state, value: old state */
#define MC_EV_GROUP_MOTION_ABORTED 10u /* axis: group; seq: the move; code: the opcode that ended it */
#define MC_EV_MOTION_ACTIVE 11u  /* a buffered move started (PLCopen Active). seq: the move; value: its target
                                  * (velocity mode: its velocity) */
#define MC_EV_IN_VELOCITY 12u    /* velocity mode reached its velocity (PLCopen InVelocity). seq: the command;
                                  * value: the velocity */
#define MC_EV_HOMING_FAILED 13u  /* homing ended without a home point (layout 1.5). seq: the MC_Home;
                                  * code: MC_HOMING_ERR_*; value: the actual position where it failed.
                                  * Posted once the axis is at rest in Standstill, not homed */
/* Safety events (16..23). */
#define MC_EV_SAFETY_STOP 16u    /* a safety stop began. code: MC_STOP_* reason, value: the
                                  * measurement (following error, position, heartbeat age s);
                                  * axis 0xFFFF for the card-wide cause (watchdog, e-stop) */
#define MC_EV_AT_REST 17u        /* the stopped axis reached rest (and, category 1, its drive was
                                  * disabled). code: MC_STOP_* reason, value: s since the stop began */
#define MC_EV_PROTOCOL_ERROR 18u /* the host broke the protocol. code: MC_PROTO_*, value: index */
#define MC_EV_SEGMENT_START 20u  /* a path segment started (layout 1.6). axis: group; seq: its command;
                                  * value: its id */
#define MC_EV_SEGMENT_END 21u    /* a path segment ended (the path left it). As MC_EV_SEGMENT_START.
                                  * Both are posted only while more than 4 * MC_MAX_AXES slots of
                                  * the event ring are free (the room kept for answers and other
                                  * events), else counted in events_lost */
#define MC_EV_PATH_LOW_WATER 22u /* the segments queued fell to group_path.low_water. axis: group;
                                  * value: segments queued */
#define MC_EV_PATH_STARVED 23u   /* the path brakes for the end of what is queued, which is not
                                  * marked MC_PATH_LAST. axis: group; value: the last id queued */
#define MC_EV_INPUT 24u          /* a debounced input edge (layout 1.7). axis: the input; code: 1
                                  * rising (active), 0 falling; value: the debounced input word */
#define MC_EV_COMPARE 25u        /* a compare channel fired or missed. axis: the channel; seq: its
                                  * MC_OP_COMPARE_ARM; code: MC_CMP_*; value: the position */
#define MC_EV_PROBE 26u          /* a touch probe captured. axis: the channel; seq: its
                                  * MC_OP_PROBE_ARM; code: the capture number since the arm
                                  * (1, 2, ...); value: the position captured */
#define MC_EV_SCOPE 29u          /* the scope (layout 1.8). seq: its MC_OP_SCOPE_ARM; code:
                                  * MC_SCOPE_EV_*; value: see there */
#define MC_EV_GANTRY_FAULT 32u   /* a gantry stopped (layout 1.10). axis: the gantry; code: MC_STOP_GANTRY_SKEW
                                  * (value: the skew, counts, of the slave beyond the limit) or the MC_STOP_*
                                  * reason of the member whose safety stop stopped the others (value:
                                  * that axis) */
#define MC_EV_GANTRY_HOMED 33u   /* MC_OP_GANTRY_HOME ended. axis: the gantry; seq: the command; code: 0
                                  * squared (value: slave 0's skew, counts) or MC_HOMING_ERR_* (value:
                                  * the axis that failed) */
#define MC_EV_PATH_PAUSED 36u    /* layout 1.11: the path came to rest on its pause point. axis: the
                                  * group; value: the id of the segment it ends (-1: none ran) */
#define MC_EV_GROUP_HOMED 30u    /* MC_OP_GROUP_HOME ended with every member homed (layout 1.11). axis:
                                  * the group; seq: the command; code: 0; value: the stages run */
#define MC_EV_GROUP_HOMING_FAILED 31u /* MC_OP_GROUP_HOME failed as a whole (layout 1.11). axis: the
                                       * group; seq: the command; code: the failing member's
                                       * MC_HOMING_ERR_* or MC_GROUP_HOME_ABORTED; value: that card
                                       * axis (-1: the group's own halt, stop or disable) */
#define MC_EV_ANALOG 34u         /* an analog input crossed its threshold (layout 1.11). axis: the input;
                                  * code: 1 above (y >= threshold), 0 below again (y <= threshold -
                                  * hysteresis); value: the filtered volts y */
#define MC_EV_SYNC_BUS 38u       /* the card's place on the sync bus changed (layout 1.12). code:
                                  * MC_BUSST_LOCKED (joined) or MC_BUSST_LOST; value: the tick */
#define MC_EV_TIMED 39u          /* a timed command ran on its tick (layout 1.12). seq: the command;
                                  * code: its opcode; value: the tick */
#define MC_EV_FREQ_DONE 37u      /* layout 1.12: a sweep ended. axis: its axis; seq: its MC_OP_FREQ_START;
                                  * code: MC_FREQ_DONE or MC_FREQ_ABORTED; value: the points measured */

/* Nack codes (mc_event.code of a NACK). Positive, one per distinct fault. */
#define MC_NACK_UNKNOWN_OPCODE 1        /* the opcode is not defined by this firmware */
#define MC_NACK_BAD_AXIS 2              /* the axis number is not one of this card's axes */
#define MC_NACK_NOT_FINITE 3            /* an argument is NaN or infinite */
#define MC_NACK_NON_POSITIVE_LIMIT 4    /* a velocity, acceleration or jerk limit is zero or
                                         * negative */
#define MC_NACK_AXIS_DISABLED 5         /* a move was commanded on a disabled axis */
#define MC_NACK_INVALID_STATE 6         /* the command is not allowed in the axis's current state */
#define MC_NACK_BAD_CONFIG 7            /* a configuration block holds a value out of its range */
#define MC_NACK_INFEASIBLE 8            /* no profile satisfies the request */
#define MC_NACK_OUT_OF_RANGE 9          /* a position or distance is beyond the card's range */
#define MC_NACK_AXES_ENABLED 10         /* the card configuration can only change while every
                                         * axis is disabled */
#define MC_NACK_LIMIT_RANGE 11  /* a kinematic limit outside its range (see MC_MAX_MOVE_TIME) */
#define MC_NACK_PLAN_CHECK 12   /* the planned profile failed the card's own check (shorter than
                                 * |d|/vmax, off its target or beyond a limit): refused, not run */
#define MC_NACK_EXPIRED 13      /* served after its deadline (the command's deadline_ms): not executed */
#define MC_NACK_OVERRIDE_RANGE 14 /* an override factor outside 0..MC_OVERRIDE_MAX */
#define MC_NACK_BAD_GROUP 16            /* no such group */
#define MC_NACK_AXIS_IN_OTHER_GROUP 17  /* an axis already belongs to another group */
#define MC_NACK_AXIS_NOT_IN_GROUP 18    /* the move needs an axis the group does not have */
#define MC_NACK_AXIS_BUSY 19            /* a group axis is moving on its own */
#define MC_NACK_AXIS_GROUPED 20         /* single-axis motion on an axis of an enabled group */
#define MC_NACK_ZERO_LENGTH_ARC 21      /* the arc has zero length (or zero radius) */
#define MC_NACK_CENTRE_NOT_EQUIDISTANT 22 /* the centre is not equidistant from start and end
                                           * within the tolerance */
#define MC_NACK_RADIUS_TOO_SMALL 23     /* the radius is shorter than half the chord */
#define MC_NACK_COLLINEAR_POINTS 24     /* the three points of a border-point arc are on one line */
#define MC_NACK_QUEUE_FULL 25           /* the group's (or the axis's) move queue is full */
#define MC_NACK_INCOMPATIBLE_MODE 26    /* the interpolator cannot run with the group's acc/dec mode */
#define MC_NACK_GROUP_DISABLED 27       /* a move on a disabled group */
#define MC_NACK_FILTER_BUSY 28          /* filters can change only while they hold no distance */
/* NURBS curves: one code per fault */
#define MC_NACK_NURBS_SEQUENCE 48       /* DATA/END without BEGIN, data out of order or missing */
#define MC_NACK_NURBS_DEGREE 49         /* degree outside 1..5 */
#define MC_NACK_NURBS_DIMENSION 50      /* the group has fewer than 2 axes */
#define MC_NACK_NURBS_CTRL_COUNT 51     /* fewer than degree+1 or more than 1024 control points */
#define MC_NACK_NURBS_KNOT_COUNT 52     /* n_knots != n_ctrl + degree + 1 */
#define MC_NACK_NURBS_KNOTS_DECREASING 53 /* knots decrease */
#define MC_NACK_NURBS_KNOT_MULTIPLICITY 54 /* an interior knot repeated more than degree times */
#define MC_NACK_NURBS_NOT_CLAMPED 55    /* end knots not repeated degree+1 times, or an empty domain */
#define MC_NACK_NURBS_WEIGHT 56         /* a weight not finite and > 0 */
#define MC_NACK_NURBS_POINT 57          /* a control point not finite */
#define MC_NACK_NURBS_START 58          /* the curve does not start where the group's path is */
#define MC_NACK_NURBS_ZERO_LENGTH 59    /* the curve has zero length */
#define MC_NACK_NURBS_KNOT 60           /* a knot not finite (NaN or infinite) */
/* Homing nack codes (64..79, layout 1.5). */
#define MC_NACK_HOMING_METHOD 64        /* a homing method the axis cannot do: an unknown number, or an
                                         * index method without MC_HOMING_INDEX */
#define MC_NACK_AXIS_HOMING 65          /* a move, jog, MC_SetPosition or MC_Home on an axis that is
                                         * homing */
/* Continuous path nack codes (80..95, layout 1.6). */
#define MC_NACK_PATH_MODE 80            /* a buffer or transition mode the card does not know, or a
                                         * time-shifted transition it cannot make (MC_TM_TIME_SHIFT) */
#define MC_NACK_PATH_ZERO_LENGTH 81     /* a line of length zero */
#define MC_NACK_PATH_OUTPUT 82          /* an output number >= MC_OUTPUTS, a value other than 0/1, or
                                         * more than MC_PATH_OUTPUTS_PENDING actions pending */
#define MC_NACK_PATH_BUSY 83            /* a path segment while group moves run, a group move while
                                         * the path runs, or group_path applied while it runs */
#define MC_NACK_PATH_ID 84              /* a segment id that is not an integer in 0..2^32-1 */
#define MC_NACK_PATH_CURVE 85           /* a NURBS path segment with a point of zero tangent, or
                                         * needing more pieces than the path buffer holds */
/* Digital I/O, compare and probe nack codes (90..99, layout 1.7). */
#define MC_NACK_IO_CONFIG 90            /* io_config: a mask bit beyond MC_INPUTS or a debounce over
                                         * MC_DEBOUNCE_MAX */
#define MC_NACK_IO_CHANNEL 91           /* a compare or probe channel that is not an integer in
                                         * 0..MC_COMPARE_CHANNELS-1 (MC_PROBE_CHANNELS-1) */
#define MC_NACK_COMPARE_MODE 92         /* an unknown mode or direction, an output >= MC_OUTPUTS, a
                                         * pulse width, low-water mark, pitch or count out of its
                                         * range, or table data of the wrong size */
#define MC_NACK_COMPARE_FULL 93         /* the table has no room for the entry's positions */
#define MC_NACK_COMPARE_ORDER 94        /* table positions not strictly monotonic in the direction */
#define MC_NACK_COMPARE_BUSY 95         /* the channel is armed (or armed in another mode, or its
                                         * table has the other direction), or its output is
                                         * another armed channel's */
#define MC_NACK_PROBE_INPUT 96          /* a probe input beyond MC_PROBE_INDEX, no edge or an
                                         * unknown flag, or a window with window_lo > window_hi */
/* Safety nack codes (32..47). */
#define MC_NACK_WATCHDOG_TRIPPED 32 /* the host watchdog fault is latched: MC_OP_SAFETY_RESET first */
#define MC_NACK_ESTOP_ACTIVE 33     /* an e-stop is latched: MC_OP_SAFETY_RESET first */
#define MC_NACK_HARD_LIMIT 34       /* the move goes further into an active limit switch */
#define MC_NACK_SOFT_LIMIT 35       /* the move goes further beyond a soft limit */
#define MC_NACK_CAUSE_ACTIVE 36     /* reset refused: the cause (alarm, encoder fault, e-stop input,
                                     * missing heartbeat) is still present */
#define MC_NACK_WATCHDOG_TIMEOUT 37 /* watchdog timeout 0 or under 1.5 x host.host_period_us */
#define MC_NACK_BAD_CATEGORY 38     /* a stop category other than 0, 1 or 2 */
#define MC_NACK_STOP_TOO_LONG 39    /* a stop ramp from max_velocity longer than the maximum stop
                                     * time, or a maximum stop time out of range */
#define MC_NACK_SESSION 40          /* a detach by a host whose session is not the attached one */
#define MC_NACK_NO_SESSION 41       /* a command the session gate refuses (see MC_OP_HOST_ATTACH): no
                                     * session attached with its watchdog armed */

/* PLCopen axis states (mc_axis_status_payload.state) */
#define MC_STATE_DISABLED 0u            /* power off */
#define MC_STATE_STANDSTILL 1u          /* powered, at rest, ready for a move */
#define MC_STATE_HOMING 2u              /* MC_Home runs */
#define MC_STATE_DISCRETE_MOTION 3u     /* a point-to-point move */
#define MC_STATE_CONTINUOUS_MOTION 4u   /* a velocity move */
#define MC_STATE_SYNCHRONIZED_MOTION 5u /* coupled to another axis or a group */
#define MC_STATE_STOPPING 6u            /* MC_Stop in progress or held (until MC_OP_STOP_RELEASE) */
#define MC_STATE_ERROR_STOP 7u          /* stopped by a fault; only MC_Reset leaves it */

/* PLCopen group states (mc_group_status_payload.state) */
#define MC_GROUP_DISABLED 0u   /* GroupDisabled */
#define MC_GROUP_STANDBY 1u    /* GroupStandby: enabled, at rest, ready for a move */
#define MC_GROUP_MOVING 2u     /* GroupMoving: interpolating */
#define MC_GROUP_HOMING 3u     /* GroupHoming: MC_OP_GROUP_HOME runs (layout 1.11) */
#define MC_GROUP_STOPPING 4u   /* GroupStopping: MC_GroupStop in progress or held */
#define MC_GROUP_ERROR_STOP 5u /* GroupErrorStop: stopped by a fault; only MC_GroupReset leaves it */

/* Fault bits (mc_axis_status_payload.faults) */
#define MC_FAULT_DAC_SATURATED (1u << 0) /* the servo output hit the DAC limit */
/* Safety fault bits (8..31): latched until MC_OP_RESET (limits: while the input or position is
 * beyond the limit). */
#define MC_FAULT_WATCHDOG (1u << 8)         /* the host watchdog tripped (the heartbeat stopped) */
#define MC_FAULT_ESTOP (1u << 9)            /* an e-stop (MC_OP_ESTOP or the card's input) stopped the axis */
#define MC_FAULT_HARD_LIMIT_POS (1u << 10)  /* at or beyond the positive limit switch */
#define MC_FAULT_HARD_LIMIT_NEG (1u << 11)  /* at or beyond the negative limit switch */
#define MC_FAULT_SOFT_LIMIT_POS (1u << 12)  /* beyond the positive soft limit */
#define MC_FAULT_SOFT_LIMIT_NEG (1u << 13)  /* beyond the negative soft limit */
#define MC_FAULT_FOLLOWING_ERROR (1u << 14) /* the following error exceeded its limit */
#define MC_FAULT_AMP_ALARM (1u << 15)       /* the amplifier's alarm input */
#define MC_FAULT_ENCODER (1u << 16)         /* encoder loss or a jump */
#define MC_FAULT_PROTOCOL (1u << 17)        /* the host broke the protocol (corrupt ring indices) */
#define MC_FAULT_STOP_TIMEOUT (1u << 18) /* a stop ran past the maximum stop time (layout 1.3) */

/* Stop categories (IEC 60204-1) */
#define MC_STOP_CAT_0 0u /* remove power now */
#define MC_STOP_CAT_1 1u /* controlled stop, then remove power */
#define MC_STOP_CAT_2 2u /* controlled stop, power kept */

/* Stop reasons (mc_axis_status_payload.stop_reason): why the axis's last motion ended.
 * 0 while a motion runs (or none has run). */
#define MC_STOP_NONE 0u             /* a motion runs, or none has run */
#define MC_STOP_DONE 1u           /* reached its target, in position */
#define MC_STOP_HALT 2u           /* MC_Halt */
#define MC_STOP_STOP 3u           /* MC_Stop */
#define MC_STOP_POWER_OFF 4u      /* MC_Power off by the host */
#define MC_STOP_HOST_DETACH 5u    /* the host closed the card (MC_OP_HOST_DETACH): halted */
#define MC_STOP_HOMING_FAILED 6u  /* homing failed (MC_EV_HOMING_FAILED): stopped, not homed */
#define MC_STOP_PROBE 7u          /* a touch probe armed with MC_PROBE_HALT captured: halted */
#define MC_STOP_GROUP_HOMING 8u   /* another member of its group failed homing (MC_OP_GROUP_HOME): halted */
#define MC_STOP_SYNC_LOST 9u      /* the card lost the sync bus's master (layout 1.12): halted */
#define MC_STOP_WATCHDOG 16u      /* host heartbeat lost */
#define MC_STOP_ESTOP_COMMAND 17u /* MC_OP_ESTOP */
#define MC_STOP_ESTOP_INPUT 18u   /* the card's e-stop input */
#define MC_STOP_HARD_LIMIT_POS 19u  /* the positive limit switch */
#define MC_STOP_HARD_LIMIT_NEG 20u  /* the negative limit switch */
#define MC_STOP_SOFT_LIMIT_POS 21u  /* the positive soft limit */
#define MC_STOP_SOFT_LIMIT_NEG 22u  /* the negative soft limit */
#define MC_STOP_FOLLOWING_ERROR 23u /* the following error exceeded its limit */
#define MC_STOP_AMP_ALARM 24u       /* the amplifier's alarm input */
#define MC_STOP_ENCODER_LOSS 25u  /* the encoder's line-break detector */
#define MC_STOP_ENCODER_JUMP 26u  /* a count change larger than physically possible */
#define MC_STOP_STARVATION 27u    /* queued motion ran out: planned stop at the end of the queue */
#define MC_STOP_CMD_RING 28u      /* command ring indices corrupt */
#define MC_STOP_EVT_RING 29u      /* event ring indices corrupt */
#define MC_STOP_GROUP 30u         /* another axis of its group tripped */
#define MC_STOP_TIMEOUT 31u       /* a stop did not end within the maximum stop time: power removed */
#define MC_STOP_HOST_CHANGED 32u  /* a host attached while the previous host's session was open */
#define MC_STOP_NO_SESSION 33u    /* motion found running with no session attached and armed */
#define MC_STOP_GANTRY_SKEW 34u   /* the gantry's skew exceeded its limit (layout 1.10) */
#define MC_STOP_GANTRY 35u        /* another axis of its gantry made a safety stop (layout 1.10) */

/* Axis I/O bits (mc_axis_status_payload.io): the FPGA's inputs and the drive-enable output */
/* Motion bits (mc_axis_status_payload.motion_flags, layout 1.5) */
#define MC_MOTION_IN_VELOCITY (1u << 0) /* velocity mode at its (overridden) velocity */
#define MC_MOTION_PAUSED (1u << 1)      /* held still by a 0 % override, in its motion state */
#define MC_MOTION_HOMED (1u << 2)       /* the position was set by homing or MC_SetPosition */
#define MC_MOTION_BUFFERED_ACTIVE (1u << 3) /* the motion running is one that was buffered */

#define MC_IO_LIMIT_POS (1u << 0)     /* the positive limit switch input */
#define MC_IO_LIMIT_NEG (1u << 1)     /* the negative limit switch input */
#define MC_IO_HOME (1u << 2)          /* the home switch input */
#define MC_IO_AMP_ALARM (1u << 3)     /* the amplifier alarm input */
#define MC_IO_ENCODER_FAULT (1u << 4) /* the encoder line-break detector */
#define MC_IO_ESTOP (1u << 5)        /* the card's e-stop input, mirrored on every axis */
#define MC_IO_DRIVE_ENABLE (1u << 8) /* output: the amplifier is enabled */

/* Card-wide safety latches (mc_safety_status.faults) */
#define MC_CARD_FAULT_WATCHDOG (1u << 0)
#define MC_CARD_FAULT_ESTOP_COMMAND (1u << 1)
#define MC_CARD_FAULT_ESTOP_INPUT (1u << 2)

/* mc_axis_safety.flags */
#define MC_AXSAFE_SOFT_LIMITS (1u << 0) /* enforce soft_limit_neg..soft_limit_pos */
#define MC_AXSAFE_HARD_LIMITS (1u << 1) /* honour the limit switch inputs */
#define MC_AXSAFE_AMP_ALARM (1u << 2)   /* honour the amplifier alarm input */
#define MC_AXSAFE_ENCODER (1u << 3)     /* honour encoder loss and jumps */
#define MC_AXSAFE_ALL 0xFu

/* Protocol errors (MC_EV_PROTOCOL_ERROR code) */
#define MC_PROTO_CMD_RING 1 /* cmd_head - cmd_tail > MC_CMD_RING_LEN */
#define MC_PROTO_EVT_RING 2 /* evt_head - evt_tail > MC_EVT_RING_LEN */

/* Servo laws (mc_axis_config.servo_law) */
#define MC_SERVO_FFPIV 0u
#define MC_SERVO_PDPLUS 1u /* Yeh eq 2.12 with the gains and drive model of axis_pdplus[axis] */
#define MC_SERVO_PIDFF 2u  /* layout 1.11: PID on the following error with velocity, acceleration
                            * and Coulomb friction feed-forward (Kim section 5), the gains of
                            * axis_pidff[axis] */

/* card writes once at boot (and servo_rate_hz on APPLY_CARD_CONFIG) */
struct mc_identity {
    uint32_t magic;
    uint16_t layout_major;
    uint16_t layout_minor;
    uint32_t fw_version; /* major << 16 | minor << 8 | patch */
    uint32_t capabilities;
    uint32_t num_axes;
    uint32_t servo_rate_hz;
    uint32_t cmd_ring_len;
    uint32_t evt_ring_len;
    uint32_t card_state;
    uint32_t _reserved[7];
};

/* host writes */
struct mc_host_ctrl {
    uint32_t heartbeat;      /* incremented by the host at least every host_period_us */
    uint32_t host_period_us; /* the host's declared heartbeat period */
    uint32_t doorbell;       /* incremented by the host after publishing commands */
    uint32_t irq_mask;       /* bit (1 << kind) enables the interrupt for that event kind */
    uint32_t host_time_ms;   /* layout 1.3: the host's monotonic clock, ms, wrapping, never 0,
                              * advanced with the heartbeat: see mc_cmd.deadline_ms */
    uint32_t _reserved[11];
};

/* card writes */
struct mc_card_ctrl {
    uint64_t tick;          /* servo ticks since boot */
    uint32_t irq_count;     /* interrupts raised since boot */
    uint32_t events_lost;   /* asynchronous events that found the event ring full */
    uint32_t cmds_accepted; /* commands consumed from the ring */
    /* layout 1.4: what the card lost since boot (wrapping); nonzero is a bug */
    uint32_t bad_accesses;  /* accesses out of range or misaligned that the card's handle on
                             * this window refused (nothing written, 0 read); the in-process
                             * sim card shares its handle with the host */
    uint32_t outbox_lost;   /* events of commands and group moves (aborts, state changes, group
                             * motion done) that found the firmware's outbox full */
    uint32_t safety_events_lost; /* safety events (stops, at rest, protocol errors) that found the
                                  * safety layer's event buffer full */
    /* layout 1.6 */
    uint32_t outputs;       /* the digital outputs, bit i = output i (MC_OUTPUTS) */
    /* layout 1.7 */
    uint32_t inputs;        /* the debounced digital inputs, polarity applied, bit i = input i */
    uint32_t inputs_raw;    /* the inputs as sampled this tick, polarity applied */
    uint32_t _reserved[5];
};

/* One ring index on its own 64-byte line. Written only by its owner. */
struct mc_ring_index {
    uint32_t value;
    uint32_t _pad[15];
};

/* host writes (command ring entries) */
struct mc_cmd {
    uint32_t seq;
    uint16_t opcode;
    uint16_t axis;
    uint32_t flags;
    uint32_t deadline_ms; /* layout 1.3: the card refuses the command (MC_NACK_EXPIRED) once
                           * host.host_time_ms has passed this (wrapping compare); 0: none */
    double args[MC_CMD_ARGS]; /* per opcode, as its MC_OP_* comment lists them; unused ones 0.
                               * In Rust each opcode's arguments are one typed struct that
                               * encodes and decodes them (firmware-proto's `cmd`) */
};

/* card writes (event ring entries) */
struct mc_event {
    uint32_t seq; /* the command's seq for ACK/NACK, 0 otherwise */
    uint16_t kind;
    uint16_t axis;
    int32_t code;
    uint32_t _reserved;
    uint64_t tick;
    double value;
};

/** FFPIV gains (Thinh Fig 5) and the velocity estimator's cut-off: part of mc_axis_config. */
struct mc_ffpiv_gains {
    /** Position gain K_P, 1/s: velocity command = kp * following error. */
    double kp;
    /** Velocity-loop integral gain K_I, 1/s. */
    double ki;
    /** Velocity-loop gain K_V, V per count/s. */
    double kv;
    /** Velocity feed-forward K_VFF into the velocity loop, fraction 0..2. */
    double kvff;
    /** Acceleration feed-forward K_AFF, V per count/s^2. */
    double kaff;
    /** Cut-off of the first-order filter on the measured velocity, Hz. */
    double vel_filter_hz;
};

/** An axis's servo configuration. Host writes; the card validates and copies it on
 * MC_OP_APPLY_AXIS_CONFIG. */
struct mc_axis_config {
    /** MC_SERVO_*: FFPIV, or PD+ with the gains of `axis_pdplus[axis]`. */
    uint32_t servo_law;
    uint32_t _reserved0;
    /** The FFPIV gains. */
    struct mc_ffpiv_gains ffpiv;
    /** Output clamp, V, 0 < limit <= 10. */
    double dac_limit_v;
    /** |target - actual| for motion done, counts. */
    double in_pos_window;
    /** |actual velocity| for motion done, counts/s. */
    double in_vel_window;
    /** Both windows held this long before motion done, s. */
    double settle_time;
    /** Layout 1.5: the largest jog velocity, counts/s (> 0). */
    double jog_max_vel;
    /** Jog acceleration and deceleration, counts/s^2 (> 0). */
    double jog_accel;
    /** Jog jerk, counts/s^3 (> 0). */
    double jog_jerk;
    /** Layout 1.8: counts per user unit, kept for hosts (the card does not use it). The card
     * writes it on MC_OP_READ_CONFIG; MC_OP_SET_SCALE sets it; MC_OP_APPLY_AXIS_CONFIG ignores
     * it. 1 at boot. */
    double scale;
    /** Layout 1.10: the modulo period, counts (0: a linear axis). The card writes it on
     * MC_OP_READ_CONFIG; MC_OP_SET_MODULO sets it; MC_OP_APPLY_AXIS_CONFIG ignores it. 0 at
     * boot. */
    double modulo;
};

/* host writes; the card validates and copies on MC_OP_APPLY_CARD_CONFIG */
struct mc_card_config {
    uint32_t servo_rate_hz;
    uint32_t _reserved[15];
};

/* host writes; the card validates and copies on MC_OP_APPLY_AXIS_FILTER. Index: MC_FEED_* */
struct mc_axis_filter {
    uint32_t kind[3];  /* MC_FILTER_* per feed type (rapid, cutting, jog) */
    uint32_t _reserved0;
    double tau[3];     /* time constant per feed type, s */
    double _reserved[3];
};

/* host writes; the card validates and copies on MC_OP_GROUP_CONFIGURE */
struct mc_group_config {
    uint32_t naxes;      /* 1..MC_MAX_AXES */
    uint8_t axes[8];     /* card axis of group axis 0 (X), 1 (Y), 2 (Z), ... */
    uint32_t accdec;     /* MC_ACCDEC_* bits, at least one */
    uint32_t interpolator; /* MC_INTERP_* */
    uint32_t home_stages; /* layout 1.11: stages of the group's home order, 0..MC_GROUP_HOME_STAGES
                           * (0: none configured; MC_OP_GROUP_HOME then needs its own order) */
    double tolerance;    /* geometry tolerance (centre equidistance, radius), counts */
    uint8_t home_order[8]; /* layout 1.11: stage k's group axes, a mask (bit i: group axis i);
                            * the stages beyond home_stages are ignored. Checked as
                            * MC_OP_GROUP_HOME's order, on MC_OP_GROUP_CONFIGURE */
    double _reserved[3];
};

/** What the card publishes about a group each tick: the payload of the group status seqlock,
 * MC_STATUS_WORDS words like the axis status. */
struct mc_group_status_payload {
    /** PLCopen group state, MC_GROUP_*. */
    uint32_t state;
    /** Moves waiting in the queue. */
    uint32_t queued;
    /** Seq of the move being interpolated, 0 if none. */
    uint32_t active_seq;
    /** Group moves started since boot (each path segment queued counts one; the member axes'
     * statistics count a whole path as one move). */
    uint32_t move_count;
    /** Distance along the active move, counts. */
    double path_pos;
    /** Its length, counts. */
    double path_len;
    /** Tangential velocity before the filters, counts/s. */
    double feed;
    /** Tangential acceleration before the filters, counts/s^2. */
    double feed_acc;
    /** Servo tick of this snapshot. */
    uint64_t tick;
    /** At the group's last coming to rest: the largest |programmed end - commanded position|
     * over its axes, the correction the snap to the end made, counts. */
    double snap_last;
    /** The largest snap_last since MC_GroupEnable, counts. */
    double snap_max;
    /** Layout 1.5: the feed override in force (lines, arcs), 0..MC_OVERRIDE_MAX. */
    double feed_override;
    /** The rapid override in force (point-to-point moves). */
    double rapid_override;
    /** Layout 1.6: segments in the path buffer not finished yet. */
    uint32_t path_queued;
    /** Free segments in the path buffer (MC_PATH_LEN - path_queued). */
    uint32_t path_free;
    /** Id of the segment running (MC_PATHST_RUNNING). */
    uint32_t path_id;
    /** MC_PATHST_* bits. */
    uint32_t path_flags;
    /** Path segments ended since MC_GroupEnable (wrapping). */
    uint32_t path_done;
    /** Layout 1.14: segments staged, waiting for MC_OP_PATH_RELEASE (a group with dimensions). */
    uint32_t path_staged;
    uint64_t _reserved[10];
    /** A mix of the words before it: the checksum the seqlock reader checks. */
    uint64_t checksum;
};

struct mc_group_status {
    uint32_t seq;
    uint32_t _pad;
    struct mc_group_status_payload p;
    uint64_t _reserved[6];
};

/** The PD+ law (Yeh eq 2.12): u = kp e + kd de/dt + kv v_ref + ka a_ref (volts, counts, s). */
struct mc_pdplus_gains {
    /** V/count. */
    double kp;
    /** V per count/s. */
    double kd;
    /** V per count/s of reference velocity. */
    double kv;
    /** V per count/s^2 of reference acceleration. */
    double ka;
};

/** The first-order drive model (Yeh eq 2.1-2.2 as corrected): dw/dt = -w/tau + (kc/tau) u,
 * dtheta/dt = ke w. */
struct mc_drive_model {
    /** Electrical gain K_c: steady motor speed per volt, (rad/s)/V. */
    double kc;
    /** Mechanical time constant, s. */
    double tau;
    /** Mechanical gain K_e, counts/rad. */
    double ke;
};

/** An axis's PD+ law and drive model. Host writes; read with axis_config on
 * MC_OP_APPLY_AXIS_CONFIG when its servo_law is MC_SERVO_PDPLUS. The model predicts u for the
 * saturation-aware feed. */
struct mc_axis_pdplus {
    /** The PD+ gains. */
    struct mc_pdplus_gains gains;
    /** The drive model. */
    struct mc_drive_model drive;
    /** Drive limit, V (at most the DAC limit). */
    double umax;
    double _reserved[8];
};

/** What the card publishes about an axis each tick (counts, seconds, volts): the payload of
 * the axis status seqlock, copied as MC_STATUS_WORDS 64-bit words. */
struct mc_axis_status_payload {
    /** Commanded (profile) position, counts. */
    double cmd_pos;
    /** Commanded velocity, counts/s. */
    double cmd_vel;
    /** Commanded acceleration, counts/s^2. */
    double cmd_acc;
    /** Actual position, counts: the encoder's, less the compensation's correction (layout 1.9:
     * where the load is; the encoder's own without compensation). */
    double act_pos;
    /** Actual velocity (filtered), counts/s. */
    double act_vel;
    /** Following error = commanded - actual position, counts. */
    double ferr;
    /** DAC output, volts. */
    double dac_v;
    /** Target of the current or last move, counts. */
    double target;
    /** PLCopen state, MC_STATE_*. */
    uint32_t state;
    /** Fault bits, MC_FAULT_*. */
    uint32_t faults;
    /** Seq of the last command accepted for this axis. */
    uint32_t last_seq;
    /** Moves started since boot: each of the axis's own moves, and each group motion it takes
     * part in counts one (a continuous path, from the group leaving Standby until it is at
     * rest again, is one move however many segments it runs). */
    uint32_t move_count;
    /** Servo tick of this snapshot. */
    uint64_t tick;
    /** Raw encoder count. */
    int64_t encoder;
    /** Max |commanded velocity| of the current or last move (statistics of the current or
     * last move are reset when a move starts; a group motion, a whole continuous path
     * included, is one move: its peaks, following error and time), counts/s. */
    double peak_vel;
    /** Max commanded acceleration in the direction of motion, counts/s^2. */
    double peak_acc;
    /** Max commanded deceleration, counts/s^2. */
    double peak_dec;
    /** Max |commanded jerk|, counts/s^3. */
    double peak_jerk;
    /** Max |following error|, counts. */
    double max_ferr;
    /** Planned profile duration, s. */
    double planned_time;
    /** From start to motion done (in position), s; 0 while moving. */
    double move_time;
    /** Payload word 19: why the last motion ended, MC_STOP_*. */
    uint32_t stop_reason;
    /** Input and drive-enable bits, MC_IO_*. */
    uint32_t io;
    /** Payload word 20: the servo law's output before the DAC clamp, V. */
    double u_request;
    /** Payload word 21 (layout 1.5): MC_MOTION_* bits. */
    uint32_t motion_flags;
    /** Buffered moves waiting in the axis's queue. */
    uint32_t queued;
    /** Payload word 22: the velocity override factor in force, 0..MC_OVERRIDE_MAX. */
    double override_factor;
    /** Payload word 23 (layout 1.9): the compensated position, the motor's reference the servo
     * follows: cmd_pos + the pitch-error and backlash correction, counts (cmd_pos without
     * compensation). */
    double comp_pos;
    /** A mix of the words before it: the checksum the seqlock reader checks. */
    uint64_t checksum;
};

/* card writes */
struct mc_axis_status {
    uint32_t seq; /* odd while the card writes the payload */
    uint32_t _pad;
    struct mc_axis_status_payload p;
    uint64_t _reserved[6];
};

/* host writes; the card validates and copies on MC_OP_APPLY_SAFETY_CONFIG */
struct mc_safety_config {
    uint32_t watchdog_timeout_us;  /* > 0 and >= 1.5 x host.host_period_us (default 100000) */
    uint32_t estop_input_category; /* MC_STOP_CAT_*: the stop the e-stop input makes (default 1) */
    uint32_t max_stop_time_us;     /* layout 1.3: every stop (halt, stop, safety stops, starvation)
                                    * ends within this, or the drive loses power at it (reason
                                    * MC_STOP_TIMEOUT); 10 ms .. 600 s (default 2 s). Each axis's
                                    * stop ramp from its max_velocity must fit in it. */
    uint32_t _reserved[13];
};

/* host writes; the card validates and copies on MC_OP_APPLY_AXIS_SAFETY */
struct mc_axis_safety {
    uint32_t flags;               /* MC_AXSAFE_* (default MC_AXSAFE_ALL & ~MC_AXSAFE_SOFT_LIMITS) */
    uint32_t limit_category;      /* MC_STOP_CAT_*: the stop a hard or soft limit makes (default 1) */
    double soft_limit_neg;        /* counts, < soft_limit_pos */
    double soft_limit_pos;        /* counts */
    double ferror;                /* following-error limit at max_velocity, counts (LinuxCNC FERROR) */
    double min_ferror;            /* the limit at rest, counts (MIN_FERROR), 0 < min <= ferror */
    double max_velocity;          /* the velocity ferror applies at, counts/s */
    double stop_decel;            /* deceleration of category 1 and 2 stops, counts/s^2 */
    double stop_jerk;             /* jerk of those stops, counts/s^3 */
    double encoder_max_velocity;  /* counts/s: a larger change in one tick is an encoder jump */
    double _reserved[7];
};

/** An axis's homing configuration (layout 1.5; see MC_OP_HOME). Host writes; the card validates
 * and copies it on MC_OP_APPLY_AXIS_HOMING. Counts and seconds. */
struct mc_axis_homing {
    /** CiA 402 homing method: 1..14, 17..30, 33, 34, 35, 37, or -1..-4 (hard stop). */
    int32_t method;
    /** MC_HOMING_* bits. */
    uint32_t flags;
    /** Velocity of the search for the switch, counts/s (> 0). */
    double search_vel;
    /** Velocity of the final approach to the edge, the index or the hard stop, counts/s
     * (0 < creep_vel <= search_vel): how far the axis moves in a servo tick there is the
     * resolution of a switch edge. */
    double creep_vel;
    /** Acceleration and deceleration, counts/s^2 (> 0). */
    double accel;
    /** Jerk, counts/s^3 (> 0). */
    double jerk;
    /** The home point reads MC_OP_HOME's position + home_offset, counts. */
    double home_offset;
    /** The whole homing ends within this, s (0 < timeout <= MC_MAX_MOVE_TIME), else
     * MC_HOMING_ERR_TIMEOUT. */
    double timeout;
    /** The farthest the axis goes from where homing began, counts (> 0), else
     * MC_HOMING_ERR_DISTANCE. */
    double max_distance;
    /** The farthest the index pulse may be beyond the edge or hard stop, counts (> 0; a
     * revolution and a margin), else MC_HOMING_ERR_NO_INDEX. Also the limit of methods 33, 34. */
    double index_distance;
    /** Hard stop: the following error that means the axis stalled, counts (> 0; with the creep
     * velocity's share of hard_stop_dwell, under the axis's following-error limit at the creep
     * velocity, else MC_OP_HOME is refused with MC_NACK_BAD_CONFIG). */
    double hard_stop_ferror;
    /** Hard stop: how long the following error stays at or above hard_stop_ferror, s (0..10). */
    double hard_stop_dwell;
    double _reserved[5];
};

/** A group's continuous path (layout 1.6). Host writes; the card validates and copies it on
 * MC_OP_APPLY_GROUP_PATH. Per group axis (group axis order), counts and seconds. */
struct mc_group_path {
    /** Checked (1..MC_PATH_LEN, reset 256) and kept: the planner looks ahead by distance, over
     * as many queued segments as braking takes (issue 32), not this many. */
    uint32_t lookahead;
    /** MC_EV_PATH_LOW_WATER when the segments queued fall to this (0: never). */
    uint32_t low_water;
    /** Tangential acceleration limit, counts/s^2 (0: from the axes). */
    double accel;
    /** Tangential jerk limit, counts/s^3 (0: from the axes). */
    double jerk;
    /** Each axis's velocity limit, counts/s (> 0). */
    double vmax[MC_MAX_AXES];
    /** Each axis's acceleration limit, counts/s^2 (> 0). */
    double amax[MC_MAX_AXES];
    /** Each axis's jerk limit, counts/s^3 (> 0). */
    double jmax[MC_MAX_AXES];
    /** The path planner's period, s (0: 1 ms), rounded to whole servo ticks (at least one,
     * at most 10 ms): the look-ahead and the speed planner run once a period, and every servo
     * tick in between follows the jerk-limited profile they chose. */
    double plan_period;
    double _reserved[5];
};

/** A group's path dimensions (layout 1.14, paths across cards; see MC_OP_APPLY_GROUP_DIMS). Host
 * writes; the card validates and copies it on MC_OP_APPLY_GROUP_DIMS. Counts and seconds. */
struct mc_group_dims {
    /** Dimensions of the path, 0 (the group's members: no staging) or 1..MC_PATH_MAX_DIMS. */
    uint32_t ndims;
    uint32_t _reserved0;
    /** Per dimension: the group axis (0..naxes-1) it drives on this card, or MC_DIM_REMOTE. */
    int32_t axis[MC_PATH_MAX_DIMS];
    /** Per dimension: velocity, acceleration and jerk limits (> 0), counts/s, /s^2, /s^3. */
    double vmax[MC_PATH_MAX_DIMS];
    double amax[MC_PATH_MAX_DIMS];
    double jmax[MC_PATH_MAX_DIMS];
    /** Per remote dimension: where it starts, counts (|start| <= MC_MAX_POSITION; ignored for
     * the group's own axes, which start where they are). */
    double start[MC_PATH_MAX_DIMS];
    double _reserved[8];
};

/** The digital inputs' configuration (layout 1.7). Host writes; the card validates and copies
 * it on MC_OP_APPLY_IO_CONFIG. All zero at boot: active high, no debounce, no events. */
struct mc_io_config {
    /** Bit i: input i is active low (the card inverts it). */
    uint32_t polarity;
    /** Bit i: MC_EV_INPUT when debounced input i becomes active. */
    uint32_t rise_events;
    /** Bit i: MC_EV_INPUT when debounced input i becomes inactive. */
    uint32_t fall_events;
    uint32_t _reserved0;
    /** Ticks input i must hold a new level before the debounced word takes it
     * (0..MC_DEBOUNCE_MAX; 0: at once). */
    uint16_t debounce[MC_INPUTS];
    uint32_t _reserved[4];
};

/** A compare channel's state (layout 1.7). Card writes; independent words, each updated in the
 * tick its event happens (the counters only grow while the channel is armed). */
struct mc_compare_status {
    /** MC_IO_IDLE, MC_IO_ARMED or MC_IO_DONE. */
    uint32_t state;
    /** The axis watched. */
    uint32_t axis;
    /** Pulses fired since the arm. */
    uint32_t fires;
    /** Positions missed since the arm. */
    uint32_t missed;
    /** Positions still to come: the series' rest, or the table's queue (free room:
     * MC_COMPARE_TABLE_LEN - pending). */
    uint32_t pending;
    /** The output pulsed. */
    uint32_t output;
    /** The next position, counts. */
    double next;
    /** The last position fired, counts. */
    double last_fired;
    /** Its instant: servo ticks since boot, with the fraction within the tick. */
    double last_fire_tick;
    /** The last position missed, counts. */
    double last_missed;
};

/** A touch probe channel's state (layout 1.7). Card writes, as mc_compare_status. */
struct mc_probe_status {
    /** MC_IO_IDLE, MC_IO_ARMED or MC_IO_DONE. */
    uint32_t state;
    /** The axis captured. */
    uint32_t axis;
    /** Captures since the arm; capture k (1, 2, ...) is position[(k - 1) % MC_PROBE_QUEUE]. */
    uint32_t captures;
    /** Edges whose position was outside the window, since the arm. */
    uint32_t outside;
    /** The last MC_PROBE_QUEUE captured positions, counts. */
    double position[MC_PROBE_QUEUE];
    /** The instant of the last capture: servo ticks since boot, with the fraction. */
    double last_tick;
    double _reserved;
};

/* card writes; independent words (not a snapshot), each written when its event happens */
struct mc_safety_status {
    uint32_t faults;              /* MC_CARD_FAULT_* latched */
    uint32_t watchdog_armed;      /* 1 while a session is attached (from its attach to its detach) */
    uint64_t last_heartbeat_tick; /* tick the card last saw host.heartbeat change */
    uint64_t watchdog_trip_tick;  /* tick the watchdog last tripped (0: never) */
    uint32_t protocol_errors;     /* MC_EV_PROTOCOL_ERROR raised since boot */
    uint32_t _reserved0;
    uint64_t stop_tick[MC_MAX_AXES]; /* tick the axis's last safety stop began */
    uint64_t rest_tick[MC_MAX_AXES]; /* tick it reached rest after it (0 while stopping) */
    double ramp_time[MC_MAX_AXES];   /* planned duration of that stop's deceleration, s */
    uint64_t trip_heartbeat_tick;    /* last_heartbeat_tick when the watchdog last tripped */
    /* layout 1.3 */
    uint32_t session;                /* the attached host's session id (0: none) */
    uint32_t host_changes;           /* attaches that found another session open (its motion was
                                      * stopped) since boot */
    uint32_t late_heartbeats;        /* heartbeats that came more than host_period_us after the
                                      * one before, since the last attach */
    uint32_t max_heartbeat_gap_us;   /* the longest gap between two heartbeats since the last
                                      * attach, us (servo-tick resolution) */
    uint64_t attach_tick;            /* tick of the last attach (0: none) */
};

/** A gantry (layout 1.10). Card writes: every tick while formed, once when dissolved. */
struct mc_gantry_status {
    /** MC_GANTRY_*: MC_GANTRY_NONE when not formed (the rest 0). */
    uint32_t phase;
    /** The master axis. */
    uint32_t master;
    /** Slaves in use. */
    uint32_t nslaves;
    /** 1 once MC_OP_GANTRY_HOME squared the bridge (cleared by a failed one or a new formation). */
    uint32_t squared;
    /** The slave axes (nslaves of them). */
    uint32_t slave[MC_GANTRY_MAX_SLAVES];
    /** The yaw loop's gains (kp, ki 1/s) and the skew limit (counts). */
    double kp;
    double ki;
    double skew_limit;
    double _reserved0;
    /** Each slave's square offset (configured), counts. */
    double offset[MC_GANTRY_MAX_SLAVES];
    /** Each slave's offset in force (hold), counts. */
    double hold[MC_GANTRY_MAX_SLAVES];
    /** Each slave's skew of the tick: slave actual - master actual - hold, counts. */
    double skew[MC_GANTRY_MAX_SLAVES];
    /** Each slave's yaw correction of the tick, counts. */
    double correction[MC_GANTRY_MAX_SLAVES];
    /** The largest |skew| of each slave while coupled since formed, counts. */
    double max_skew[MC_GANTRY_MAX_SLAVES];
};

/** Synchronised motion (layout 1.7 (sync)). Card writes, every tick. */
struct mc_sync_status {
    /** The auxiliary encoder inputs, counts. */
    int64_t aux_count[MC_AUX_ENCODERS];
    /** The ratio of each axis's coupling (slave counts per master count; 0: not coupled). */
    double gear_ratio[MC_MAX_AXES];
    /** Each axis's PT/PVT stream: points queued, and free. */
    uint32_t pvt_queued[MC_MAX_AXES];
    uint32_t pvt_free[MC_MAX_AXES];
};

/** The scope's configuration (layout 1.8). Host writes; the card validates and copies it on
 * MC_OP_SCOPE_CONFIGURE. All zero at boot (n_channels 0: not configured). */
struct mc_scope_config {
    /** Channels sampled, 1..MC_SCOPE_CHANNELS. */
    uint32_t n_channels;
    /** A sample every divider ticks, 1..MC_SCOPE_DIVIDER_MAX. */
    uint32_t divider;
    /** Channel k's source, MC_SCOPE_SOURCE(MC_SIG_*, index). */
    uint32_t source[MC_SCOPE_CHANNELS];
    /** MC_SCOPE_ONE_SHOT or MC_SCOPE_CONTINUOUS. */
    uint32_t mode;
    /** MC_SCOPE_TRIG_*. */
    uint32_t trigger;
    /** MC_SCOPE_TRIG_LEVEL: the channel compared with level. */
    uint32_t trigger_channel;
    /** MC_SCOPE_TRIG_INPUT: the input, 0..MC_INPUTS-1. */
    uint32_t trigger_input;
    /** MC_SCOPE_RISING, _FALLING or _EITHER (level and input triggers). */
    uint32_t edge;
    /** Samples kept from before the trigger, 0..MC_SCOPE_PRETRIGGER_MAX. */
    uint32_t pre_trigger;
    /** One-shot: samples from the trigger sample on, >= 1. */
    uint32_t post_trigger;
    uint32_t _reserved0;
    /** MC_SCOPE_TRIG_LEVEL: the level, in the channel's unit. */
    double level;
    uint64_t _reserved[4];
};

/** The scope's state (layout 1.8). Card writes; independent words, updated each tick the
 * scope runs and by its commands. */
struct mc_scope_status {
    /** MC_SCOPE_IDLE, _WAITING, _CAPTURING or _DONE. */
    uint32_t state;
    /** The seq of the MC_OP_SCOPE_ARM of the capture. */
    uint32_t arm_seq;
    /** Channels per sample of the capture. */
    uint32_t n_channels;
    /** The divider of the capture. */
    uint32_t divider;
    /** The trigger sample's servo tick (0: not triggered yet). */
    uint64_t trigger_tick;
    /** Samples put in the ring since the arm. */
    uint64_t samples;
    /** Samples lost since the arm (the ring was full). */
    uint64_t lost;
    /** The pre-trigger samples the capture took, put in the ring (or lost) first: pre_trigger,
     * or fewer when the trigger came before that many samples were taken since the arm (0
     * until the trigger). */
    uint32_t pre_captured;
    uint32_t _reserved0;
    uint64_t _reserved[2];
};

/** A scope ring entry (layout 1.8): one sample. Card writes. */
struct mc_scope_sample {
    /** The servo tick it was taken at. */
    uint64_t tick;
    /** Channel k's value (channels >= n_channels: 0). */
    double value[MC_SCOPE_CHANNELS];
};

/** One compensation point (layout 1.9), counts. */
struct mc_comp_point {
    /** Position, in the axis's (homed) frame. */
    double position;
    /** Correction added moving forward (or at rest after a forward motion). */
    double forward;
    /** Correction added moving in reverse (equal to forward without MC_COMP_BIDIR). */
    double reverse;
};

/** A compensation table read back (layout 1.9, MC_OP_COMP_READ). Card writes, before the ack. */
struct mc_comp_readback {
    /** The axis. */
    uint32_t axis;
    /** The table's points (0: no table). */
    uint32_t points;
    /** The index of `point[0]`. */
    uint32_t first;
    /** Points written here (at most MC_COMP_READ_MAX). */
    uint32_t count;
    /** MC_COMP_BIDIR. */
    uint32_t flags;
    uint32_t _reserved0[3];
    /** The bound, backlash, ramp velocity and acceleration (0 for an axis without compensation). */
    double bound;
    double backlash;
    double ramp_vel;
    double ramp_acc;
    double _reserved[4];
    struct mc_comp_point point[MC_COMP_READ_MAX];
};

/** The PID + feed-forward law (layout 1.11, Kim section 5): on the following error
 * e = x_ref - x (counts), u = kp e + I + kd de/dt (through a first-order filter at
 * d_filter_hz) + kvff v_ref + kaff a_ref + friction sign(v_ref) (0 while |v_ref| <= deadband).
 * I integrates ki e and is clamped (anti-windup) to the DAC limit; it stops integrating while
 * the output is saturated in the error's direction. Host writes; read with axis_config on
 * MC_OP_APPLY_AXIS_CONFIG when its servo_law is MC_SERVO_PIDFF (a switch to it at rest is
 * bumpless: the integrator starts from the output of the tick). Volts, counts, seconds. */
struct mc_axis_pidff {
    /** Proportional gain, V/count. */
    double kp;
    /** Integral gain, V/(count s). */
    double ki;
    /** Derivative gain, V per count/s. */
    double kd;
    /** Velocity feed-forward, V per count/s of v_ref. */
    double kvff;
    /** Acceleration feed-forward, V per count/s^2 of a_ref. */
    double kaff;
    /** Coulomb friction feed-forward, V (times the sign of v_ref). */
    double friction;
    /** |v_ref| at or below which the friction feed-forward is 0, counts/s (> 0). */
    double friction_deadband;
    /** The derivative's first-order filter cut-off, Hz (> 0; at or above the Nyquist frequency
     * it filters next to nothing). */
    double d_filter_hz;
    double _reserved[8];
};

/** One biquad filter (layout 1.11): its kind and parameters as set (MC_OP_SERVO_FILTER_SET)
 * and the coefficients the card designed, normalised (a0 = 1). */
struct mc_biquad {
    /** MC_BIQUAD_* (MC_BIQUAD_NONE: the slot is empty, the rest 0). */
    uint32_t kind;
    uint32_t _reserved0;
    double freq_hz;
    double damping;
    double depth_db;
    double freq2_hz;
    double b0;
    double b1;
    double b2;
    double a1;
    double a2;
    double _reserved[2];
};

/** An axis's biquad filters (layout 1.11). Card writes: at boot, on a servo rate change, and
 * before the ack of each MC_OP_SERVO_FILTER_SET / _CLEAR of the axis. */
struct mc_servo_filters {
    /** Bit k: slot k holds a filter. */
    uint32_t active;
    uint32_t _reserved0[3];
    struct mc_biquad slot[MC_BIQUADS];
};

/** Analog I/O and the PSO (layout 1.11). Card writes, at the end of a tick in which any of it
 * changed (and whole every 64 ticks); independent words, each the value of that tick. */
struct mc_analog_status {
    /** Each input's ADC sample of the tick, V (a multiple of MC_ADC_LSB). */
    double input_raw[MC_ANALOG_INPUTS];
    /** Each input filtered, V. */
    double input[MC_ANALOG_INPUTS];
    /** Each spare DAC's output, V (the PSO's, or MC_OP_ANALOG_OUTPUT's). */
    double output[MC_ANALOG_OUTPUTS];
    /** Bit i: input i is above its threshold. */
    uint32_t above;
    /** Bit i: input i posts MC_EV_ANALOG going above / below (MC_ANALOG_EV_RISE / _FALL). */
    uint32_t rise_events;
    uint32_t fall_events;
    /** MC_PSO_OFF, MC_PSO_CLOSED or MC_PSO_ON. */
    uint32_t pso_state;
    /** Each input's cut-off (Hz, 0: none), threshold and hysteresis (V). */
    double cutoff_hz[MC_ANALOG_INPUTS];
    double threshold[MC_ANALOG_INPUTS];
    double hysteresis[MC_ANALOG_INPUTS];
    /** The PSO's configuration (as MC_OP_PSO's arguments; all 0 while off). */
    uint32_t pso_group;
    uint32_t pso_output;
    uint32_t pso_gate;
    uint32_t pso_flags;
    double pso_min;
    double pso_max;
    double pso_v_ref;
    double pso_pwm_hz;
    double pso_filter_hz;
    /** The group's actual tangential speed of the tick, counts/s (0 while off). */
    double pso_speed;
    /** The PSO's output of the tick: V, or the duty 0..1 (MC_PSO_PWM). */
    double pso_value;
    double _reserved[3];
};

/** Who the card is and its place on the sync bus (layout 1.12). Card writes, every tick. */
struct mc_card_info {
    /** The card's name, NUL-padded: `card-emu --name`, "sim", or the board's EEPROM name. */
    char name[32];
    /** The board's serial number (0: none). */
    uint64_t serial;
    /** MC_BUS_ALONE, MC_BUS_MASTER or MC_BUS_FOLLOWER. */
    uint32_t sync_role;
    /** MC_BUSST_FREE, MC_BUSST_LOCKED or MC_BUSST_LOST. */
    uint32_t sync_state;
    /** A follower: the master's name, NUL-padded (empty otherwise). */
    char sync_master[32];
    /** A master: its followers on the bus now. */
    uint32_t sync_followers;
    /** Timed commands held (MC_OP_AT_TICK). */
    uint32_t timed_held;
    /** The tick of the earliest held one (0: none). */
    uint64_t timed_next;
    /** Commits seen (MC_OP_SYNC_COMMIT here or on the bus). */
    uint32_t commits;
    /** Times the master was lost since boot. */
    uint32_t sync_losses;
    uint32_t _reserved[8];
};

/** One point of a sweep (layout 1.12): the frequency run and the single-bin DFT of each signal
 * over its measured window (see MC_OP_FREQ_START). */
struct mc_freq_point {
    /** The frequency run, Hz (cycles servo_rate_hz / M). */
    double hz;
    /** The injected sine d: counts (MC_FREQ_REF) or V. */
    double d_re;
    double d_im;
    /** The encoder position less the position held, counts. */
    double x_re;
    double x_im;
    /** The DAC output, V. */
    double u_re;
    double u_im;
    /** The measured window's length, ticks (M). */
    uint32_t window;
    uint32_t _reserved0;
};

/** The frequency-response sweep (layout 1.12). Card writes: the header when a sweep starts and
 * ends, each point (then done) as it is measured. */
struct mc_freq_status {
    /** MC_FREQ_IDLE, _RUNNING, _DONE, _ABORTED. */
    uint32_t state;
    /** The axis swept. */
    uint32_t axis;
    /** MC_FREQ_REF or MC_FREQ_OUTPUT. */
    uint32_t mode;
    /** The points asked for. */
    uint32_t points;
    /** The points measured so far (point[0..done]). */
    uint32_t done;
    /** The MC_OP_FREQ_START's seq. */
    uint32_t seq;
    /** Periods measured per window (as asked). */
    uint32_t cycles;
    uint32_t _reserved0;
    double from_hz;
    double to_hz;
    /** Counts (MC_FREQ_REF) or V (MC_FREQ_OUTPUT). */
    double amplitude;
    double settle_s;
    /** The position held when the sweep started, counts. */
    double hold_pos;
    double _reserved[3];
    struct mc_freq_point point[MC_FREQ_POINTS_MAX];
};

/* The whole window. */
struct mc_dpram {
    struct mc_identity identity;
    struct mc_host_ctrl host;
    struct mc_card_ctrl card;
    uint8_t _reserved0[64];
    struct mc_ring_index cmd_head; /* host writes */
    struct mc_ring_index cmd_tail; /* card writes */
    struct mc_ring_index evt_head; /* card writes */
    struct mc_ring_index evt_tail; /* host writes */
    struct mc_cmd cmd_ring[MC_CMD_RING_LEN];
    struct mc_event evt_ring[MC_EVT_RING_LEN];
    struct mc_card_config card_config;
    struct mc_axis_config axis_config[MC_MAX_AXES];
    struct mc_axis_status axis_status[MC_MAX_AXES];
    /* layout 1.1 */
    struct mc_axis_filter axis_filter[MC_MAX_AXES];
    struct mc_group_config group_config[MC_MAX_GROUPS];
    struct mc_group_status group_status[MC_MAX_GROUPS];
    struct mc_axis_pdplus axis_pdplus[MC_MAX_AXES];
    struct mc_safety_config safety;                  /* host writes */
    struct mc_axis_safety axis_safety[MC_MAX_AXES];  /* host writes */
    struct mc_safety_status safety_status;           /* card writes */
    /* layout 1.5 */
    struct mc_axis_homing axis_homing[MC_MAX_AXES];  /* host writes */
    /* layout 1.6 */
    struct mc_group_path group_path[MC_MAX_GROUPS];  /* host writes */
    /* layout 1.7 */
    struct mc_io_config io_config;                              /* host writes */
    struct mc_compare_status compare_status[MC_COMPARE_CHANNELS]; /* card writes */
    struct mc_probe_status probe_status[MC_PROBE_CHANNELS];       /* card writes */
    /* layout 1.7: synchronised motion */
    struct mc_sync_status sync_status;                            /* card writes */
    /* layout 1.8: the scope */
    struct mc_scope_config scope_config;                          /* host writes */
    struct mc_scope_status scope_status;                          /* card writes */
    uint8_t _reserved1[32];                                       /* the ring indices on their own lines */
    struct mc_ring_index scope_head;                              /* card writes */
    struct mc_ring_index scope_tail;                              /* host writes */
    struct mc_scope_sample scope_ring[MC_SCOPE_RING_LEN];         /* card writes */
    /* layout 1.9 */
    struct mc_comp_readback comp_readback;                        /* card writes */
    /* layout 1.10 */
    struct mc_gantry_status gantry_status[MC_MAX_GANTRIES];       /* card writes */
    /* layout 1.11 */
    struct mc_axis_pidff axis_pidff[MC_MAX_AXES];                 /* host writes */
    struct mc_servo_filters servo_filters[MC_MAX_AXES];           /* card writes */
    struct mc_analog_status analog_status;                        /* card writes */
    /* layout 1.12 */
    struct mc_card_info card_info;                                /* card writes */
    struct mc_freq_status freq_status;                            /* card writes */
    /* layout 1.14 */
    struct mc_group_dims group_dims[MC_MAX_GROUPS];               /* host writes */
};

#define MC_DPRAM_SIZE 1048576u /* the mapped window (1 MiB; 32 KiB before layout 1.8);
                                * sizeof(struct mc_dpram) fits in it */

#endif /* MC_DPRAM_H */
