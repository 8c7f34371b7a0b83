//! `mcctl`: the motion card from the command line, for machine builders who do not want to
//! write code.
//!
//! ```text
//! mcctl plan 100000 --vmax 200000 --amax 2e6 --jmax 1e8            # the S-curve the card plans
//! mcctl plan 100000 --vmax 2e5 --amax 2e6 --dmax 1e6 --jmax 1e8 --jdec 2e7 --json
//! mcctl plan 100000 --vmax 5e19 --amax 2e6 --jmax 1e8 --servo-rate 20000   # limits in the card's range
//! mcctl plan 100 --vmax 10 --amax 100 --jmax 1e3 --v0 -15 --a0 0     # from any state (time-optimal)
//! mcctl --card emu:bench1 info                       # firmware, layout, axes, servo rate
//! mcctl scope --move 20000 --enable --pre 100 --trigger level:0:1 --csv m.csv --svg m.svg
//! MOTIONCARD_TRACE=run.trace ./my_program && mcctl replay run.trace   # API trace, replayed
//! mcctl --card emu:bench1 status --watch             # axes and groups, live (--json: one object)
//! mcctl --card emu:bench1 enable 0 1                 # MC_Power (disable, stop, reset likewise)
//! mcctl --card emu:bench1 move 0 -25000 --vmax 1e5 --amax 1e6 --jmax 5e7 --enable
//! mcctl --card emu:bench1 move 0 20000 --velocity --for 2   # velocity mode for 2 s
//! mcctl --card emu:bench1 override 0 0.5             # 50 %
//! mcctl --card emu:bench1 home 0 --method 37 --position 100   # MC_Home (CiA 402 method)
//! mcctl --card emu:bench1 jog 0 -20000 --for 1.5     # hold the button 1.5 s, then release
//! mcctl run examples/gcode/part.ngc --tolerance 0.01 --json   # a G-code program, measured
//! mcctl --card emu:bench1 io --set-outputs 0x0F 0x05   # digital outputs, then inputs/outputs
//! mcctl --card emu:bench1 pvt 0 points.csv --vmax 1e5 --amax 1e6 --enable   # a PT/PVT stream
//! mcctl compare 0 --output 3 --series 1000,500,20 --move 12000 --enable   # EQU pulses
//! mcctl probe 0 --edge both --continuous --move 20000 --enable     # index-pulse latches
//! mcctl gear 1 --master 0 --ratio -3/2 --move 40000 --enable       # MC_GearIn, master moved
//! mcctl cam 1 knife.csv --master 0 --cubic --periodic --move 7200 --enable   # MC_CamIn
//! mcctl --card emu:bench1 config save bench1.toml   # what the card holds (read back), as TOML
//! mcctl --card emu:bench1 config load bench1.toml   # checked whole first; exit 2: bad file
//! mcctl --card emu:bench1 config diff bench1.toml --json   # exit 0: equal, 1: different
//! mcctl --card emu:bench1 serve --listen 127.0.0.1:8080 --axis 0   # the tuning page (open the
//!                                                    # http://…/#token=… address it prints)
//! ```
use clap::{Args, Parser, Subcommand, ValueEnum};
use mcctl::cli::{self, ComparePositions, Coupling, MoveCmd, Travel};
use motioncard_sdk::plan::{Limits, OtgLimits, PlanError, Profile, Trajectory};
use motioncard_sdk::{
    CamSettings, Card, Direction, Master, MoveKind, MoveLimits, ProbeTrigger, SyncLimits,
    VelocityLimits,
};
use std::process::ExitCode;
use std::time::Duration;

#[derive(Parser)]
#[command(name = "mcctl", version, about = "Motion card command-line tool")]
struct Cli {
    /// The card: `sim` (an emulated card in this process), `emu:NAME` (a card-emu process),
    /// `uio:/dev/uioN` or `pci:DDDD:BB:DD.F`.
    #[arg(long, global = true, default_value = "sim")]
    card: String,
    #[command(subcommand)]
    command: Cmd,
}

/// Limits of a move, in the axis's units (counts unless the program set a scale).
#[derive(Args, Clone, Copy)]
struct MoveArgs {
    /// Maximum velocity (position moves).
    #[arg(long, allow_negative_numbers = true, default_value_t = 100_000.0)]
    vmax: f64,
    /// Maximum acceleration.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1e6)]
    amax: f64,
    /// Maximum deceleration (default: --amax).
    #[arg(long, allow_negative_numbers = true)]
    dmax: Option<f64>,
    /// Jerk.
    #[arg(long, allow_negative_numbers = true, default_value_t = 5e7)]
    jmax: f64,
}

impl MoveArgs {
    fn limits(&self) -> MoveLimits {
        MoveLimits::new(self.vmax, self.amax, self.jmax)
            .deceleration(self.dmax.unwrap_or(self.amax))
    }
}

/// The move that exercises a compare, a probe or a coupling, and how long to watch without
/// one.
#[derive(Args, Clone, Copy)]
struct TravelArgs {
    /// Move the axis (compare, probe) or the master axis (gear, cam) to this absolute
    /// position, and watch until it is there.
    #[arg(long = "move", allow_negative_numbers = true, value_name = "TARGET")]
    target: Option<f64>,
    #[command(flatten)]
    limits: MoveArgs,
    /// Without --move: seconds to watch.
    #[arg(long = "for", default_value_t = 1.0)]
    hold: f64,
    /// Power the axes on first if they are disabled. compare, probe, gear and cam power only
    /// the axes they move, once what they arm or load is accepted, and power them off again
    /// when they end, however they end.
    #[arg(long)]
    enable: bool,
}

impl TravelArgs {
    fn travel(&self, axis: usize) -> Option<Travel> {
        self.target.map(|target| Travel {
            axis,
            target,
            limits: self.limits.limits(),
        })
    }

    fn hold(&self) -> Result<Duration, String> {
        if self.hold.is_finite() && self.hold >= 0.0 {
            Ok(Duration::from_secs_f64(self.hold))
        } else {
            Err(format!(
                "--for must be a number of seconds >= 0, got {}",
                self.hold
            ))
        }
    }
}

/// A slave's limits while it engages (gear, cam).
#[derive(Args, Clone, Copy)]
struct SyncArgs {
    /// The slave's velocity limit while it catches up.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1e6)]
    slave_vmax: f64,
    /// The slave's acceleration limit.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1e7)]
    slave_amax: f64,
    /// The slave's jerk limit.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1e9)]
    slave_jmax: f64,
}

#[derive(Clone, Copy, ValueEnum)]
enum DirArg {
    Positive,
    Negative,
    Either,
}

impl From<DirArg> for Direction {
    fn from(d: DirArg) -> Self {
        match d {
            DirArg::Positive => Direction::Positive,
            DirArg::Negative => Direction::Negative,
            DirArg::Either => Direction::Either,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum EdgeArg {
    Rising,
    Falling,
    Both,
}

/// `mcctl config`: card configuration files (layout 1.8).
#[derive(Subcommand)]
enum ConfigCmd {
    /// Write what the card holds (read back from the card) to FILE as TOML (`-`: standard
    /// output).
    Save { file: std::path::PathBuf },
    /// Check FILE whole against the card (exit status 2, naming the key and its line, and
    /// nothing applied, when anything is wrong), then apply the sections that differ.
    Load {
        file: std::path::PathBuf,
        /// One JSON object (the sections applied) instead of lines.
        #[arg(long)]
        json: bool,
    },
    /// The keys where FILE and the card differ (FILE checked as by load). Exit status 0 when
    /// they are equal, 1 when they differ, like diff.
    Diff {
        file: std::path::PathBuf,
        /// One JSON array of {key, file, card} instead of lines.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Subcommand)]
enum Cmd {
    /// Card configuration files in TOML: save, load, diff (every value in the card's units).
    Config {
        #[command(subcommand)]
        action: ConfigCmd,
    },
    /// Print the seven-segment S-curve the card plans for one axis (Thinh eq 1–28): the phase
    /// durations, total time, peak velocity and acceleration. Units are the caller's (counts and
    /// seconds on the card).
    Plan {
        /// Distance to travel (signed).
        #[arg(allow_hyphen_values = true)]
        distance: f64,
        // Negative numbers are values here, so `--dmax -3` gets "must be greater than zero"
        // rather than clap's "unexpected argument".
        /// Maximum velocity.
        #[arg(long, allow_negative_numbers = true)]
        vmax: f64,
        /// Maximum acceleration.
        #[arg(long, allow_negative_numbers = true)]
        amax: f64,
        /// Maximum jerk (phases 1 and 3; also 5 and 7 unless --jdec).
        #[arg(long, allow_negative_numbers = true)]
        jmax: f64,
        /// Maximum deceleration (default: --amax).
        #[arg(long, allow_negative_numbers = true)]
        dmax: Option<f64>,
        /// Jerk of the deceleration phases 5 and 7 (default: --jmax).
        #[arg(long, allow_negative_numbers = true)]
        jdec: Option<f64>,
        /// Start velocity, along the direction of motion (0..=--vmax). With --a0: signed, in
        /// the world frame, any value (a start beyond --vmax is braked first).
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        v0: f64,
        /// End velocity, along the direction of motion (0..=--vmax). With --a0: signed, in the
        /// world frame, within ±--vmax.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        v1: f64,
        /// Start acceleration, signed (world frame). Plans the time-optimal trajectory from
        /// any state (Ruckig's position interface, `motion::otg`) instead of the S-curve:
        /// --v0 and --v1 are then signed, --v0 may lie beyond --vmax and --a0 beyond the
        /// limits; the limits are --amax ahead, --dmax behind and the smaller jerk.
        #[arg(long, allow_negative_numbers = true)]
        a0: Option<f64>,
        /// Servo rate of the card, Hz (1000..=20000): the range the card accepts for each limit
        /// depends on it.
        #[arg(long, default_value_t = 10_000)]
        servo_rate: u32,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// The card's digital inputs (debounced and raw) and outputs.
    Io {
        /// First set the outputs in MASK to VALUE (decimal or 0x hex).
        #[arg(long, num_args = 2, value_names = ["MASK", "VALUE"], value_parser = parse_word)]
        set_outputs: Option<Vec<u32>>,
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Stream a PT/PVT file through the axis's point buffer and wait for its end: one
    /// `time, position[, velocity]` per line (seconds from the start, the axis's units; `#`
    /// comments). Unless every line gives a velocity (or with --pt) the card estimates them
    /// (PT).
    Pvt {
        axis: usize,
        file: std::path::PathBuf,
        /// PT: ignore the velocities, let the card estimate them.
        #[arg(long)]
        pt: bool,
        /// Velocity limit of every segment.
        #[arg(long, allow_negative_numbers = true, default_value_t = 100_000.0)]
        vmax: f64,
        /// Acceleration limit of every segment.
        #[arg(long, allow_negative_numbers = true, default_value_t = 1e6)]
        amax: f64,
        /// Enable the axis first if it is disabled.
        #[arg(long)]
        enable: bool,
        /// One JSON object instead of a line.
        #[arg(long)]
        json: bool,
    },
    /// Position compare (EQU output): pulse an output as the axis crosses positions. Arms
    /// the channel, runs --move (or watches --for seconds), reports the fires and misses the
    /// card counted with the positions of its events (misses of one tick share one event: the
    /// last position), and disarms.
    Compare {
        axis: usize,
        /// The output pulsed (0..16).
        #[arg(long)]
        output: u32,
        /// The compare channel (0..4).
        #[arg(long, default_value_t = 0)]
        channel: usize,
        /// Fire once, at this position.
        #[arg(long, allow_negative_numbers = true, value_name = "POSITION")]
        at: Option<f64>,
        /// Fire COUNT times from START, PITCH apart in the direction.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_names = ["START,PITCH,COUNT"])]
        series: Option<Vec<f64>>,
        /// Fire at the positions of this file (one per line, strictly monotonic in the
        /// direction), streamed into the channel's table as it empties.
        #[arg(long, value_name = "FILE")]
        table: Option<std::path::PathBuf>,
        /// The direction of crossing that fires.
        #[arg(long, value_enum, default_value = "positive")]
        direction: DirArg,
        /// Pulse width, µs.
        #[arg(long, default_value_t = 10)]
        pulse_us: u32,
        #[command(flatten)]
        travel: TravelArgs,
        #[arg(long)]
        json: bool,
    },
    /// Touch probe (MC_TouchProbe): latch the axis's position at an input edge or at the
    /// encoder's index pulse. Arms, runs --move (or watches --for seconds), reports every
    /// capture, and aborts the probe (MC_AbortTrigger).
    Probe {
        axis: usize,
        /// The probe channel (0..4).
        #[arg(long, default_value_t = 0)]
        channel: usize,
        /// The input (0..16); without it, the encoder's index pulse.
        #[arg(long)]
        input: Option<u32>,
        /// The edge that captures.
        #[arg(long, value_enum, default_value = "rising")]
        edge: EdgeArg,
        /// Keep capturing (else the first edge only).
        #[arg(long)]
        continuous: bool,
        /// Only edges with the axis in LO..=HI count.
        #[arg(long, num_args = 2, allow_negative_numbers = true, value_names = ["LO", "HI"])]
        window: Option<Vec<f64>>,
        #[command(flatten)]
        travel: TravelArgs,
        #[arg(long)]
        json: bool,
    },
    /// Electronic gearing (MC_GearIn): the slave follows the master at an integer ratio; the
    /// master runs --move (or an auxiliary encoder is watched --for seconds); then MC_GearOut
    /// and a halt. Reports both travels and the slave's error against the ratio.
    Gear {
        slave: usize,
        /// N (axis N's commanded position), actual:N (its encoder) or aux:K (an auxiliary
        /// encoder).
        #[arg(long, value_parser = cli::parse_master)]
        master: Master,
        /// Slave counts per master count, NUM/DEN (integers).
        #[arg(long, default_value = "1/1", allow_hyphen_values = true, value_parser = parse_ratio)]
        ratio: (i64, i64),
        #[command(flatten)]
        sync: SyncArgs,
        #[command(flatten)]
        travel: TravelArgs,
        #[arg(long)]
        json: bool,
    },
    /// Camming (MC_CamTableSelect, MC_CamIn): load a cam table (one `master, slave` per line),
    /// couple the slave to the master through it, run the master's --move, MC_CamOut and a halt.
    /// Reports the slave's end position against the table's.
    Cam {
        slave: usize,
        file: std::path::PathBuf,
        #[arg(long, value_parser = cli::parse_master)]
        master: Master,
        /// The card's table (0..4) loaded.
        #[arg(long, default_value_t = 0)]
        table: usize,
        /// Cubic spline (else linear).
        #[arg(long)]
        cubic: bool,
        /// The table repeats every master span.
        #[arg(long)]
        periodic: bool,
        #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
        master_offset: f64,
        #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
        slave_offset: f64,
        #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
        master_scale: f64,
        #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
        slave_scale: f64,
        /// Start where the slave stands (PLCopen StartMode relative; else absolute, ramped in).
        #[arg(long)]
        relative: bool,
        #[command(flatten)]
        sync: SyncArgs,
        #[command(flatten)]
        travel: TravelArgs,
        #[arg(long)]
        json: bool,
    },
    /// The axes' state, positions, velocity, following error, queue, override and faults, and
    /// the groups' state, queues, path segment and feed.
    Status {
        /// Only this axis.
        #[arg(long)]
        axis: Option<usize>,
        /// Refresh until interrupted (a live table; with --json one object per line).
        #[arg(long)]
        watch: bool,
        /// --watch: seconds between refreshes.
        #[arg(long, default_value_t = 0.2)]
        interval: f64,
        /// --watch: stop after this many refreshes (0: never).
        #[arg(long, default_value_t = 0)]
        count: u64,
        /// One JSON object (`tick`, `axes`, `groups`) instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// The card's scope: a one-shot capture of up to 16 channels (every --divider-th servo
    /// tick), from a trigger with --pre samples before it, of a --move of --axis started while
    /// armed; written to --csv and --svg, summarised per channel.
    Scope {
        /// A channel SIGNAL[:INDEX] (repeat for more, up to 16): cmd_pos, cmd_vel, cmd_acc,
        /// act_pos, act_vel, ferr, dac, u_request, encoder, servo_p, servo_i, servo_d, servo_ff
        /// (of an axis), path_speed, path_acc, path_pos (of a group), inputs, outputs,
        /// inputs_raw. Default: cmd_pos, act_pos, ferr and dac of --axis.
        #[arg(long = "channel", value_parser = cli::parse_source)]
        channels: Vec<motioncard_sdk::Source>,
        /// Samples from the trigger on.
        #[arg(long, default_value_t = 2000)]
        samples: u32,
        /// Samples kept from before the trigger.
        #[arg(long, default_value_t = 0)]
        pre: u32,
        /// A sample every N servo ticks.
        #[arg(long, default_value_t = 1)]
        divider: u32,
        /// immediate, command, fault, level:CHANNEL:LEVEL[:rising|falling|either] (CHANNEL:
        /// its place in the --channel list, from 0) or input:N[:EDGE].
        #[arg(long, default_value = "immediate", allow_hyphen_values = true, value_parser = cli::parse_trigger)]
        trigger: motioncard_sdk::ScopeTrigger,
        /// The axis of the default channels and of --move.
        #[arg(long, default_value_t = 0)]
        axis: usize,
        /// Write the samples here (tick, seconds from the trigger, one column a channel).
        #[arg(long)]
        csv: Option<std::path::PathBuf>,
        /// Plot the channels against time here.
        #[arg(long)]
        svg: Option<std::path::PathBuf>,
        /// Seconds the whole capture may take.
        #[arg(long, default_value_t = 10.0)]
        timeout: f64,
        #[command(flatten)]
        travel: TravelArgs,
        #[arg(long)]
        json: bool,
    },
    /// Replay an API trace (recorded with MOTIONCARD_TRACE=FILE or Card::open_traced) against
    /// an emulated card (`--card sim`) and report the first answer or event that differs (exit
    /// status 1 when one does).
    Replay {
        file: std::path::PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// What the card is: firmware and layout versions, axes, groups, servo rate, capabilities.
    Info {
        #[arg(long)]
        json: bool,
    },
    /// MC_Power on: enable the axes.
    Enable {
        #[arg(required = true)]
        axes: Vec<usize>,
    },
    /// MC_Power off: disable the axes.
    Disable {
        #[arg(required = true)]
        axes: Vec<usize>,
    },
    /// MC_Stop: decelerate to rest, then release the stop (the axis in Standstill again;
    /// --hold keeps it Stopping until the session ends).
    Stop {
        axis: usize,
        #[arg(long, allow_negative_numbers = true, default_value_t = 1e6)]
        dmax: f64,
        #[arg(long, allow_negative_numbers = true, default_value_t = 5e7)]
        jmax: f64,
        #[arg(long)]
        hold: bool,
    },
    /// MC_Reset: the axes out of ErrorStop; --faults first resets the card's latched safety
    /// faults (e-stop, host watchdog).
    Reset {
        /// The axes (none: every axis in ErrorStop).
        axes: Vec<usize>,
        #[arg(long)]
        faults: bool,
    },
    /// MC_MoveAbsolute (default), MC_MoveRelative, MC_MoveAdditive or MC_MoveVelocity, and wait
    /// until done (velocity mode: run --for seconds, then halt). The axis runs only while
    /// mcctl does: a host that leaves closes its session, and the card halts what it started.
    Move {
        axis: usize,
        /// Target, distance or velocity.
        #[arg(allow_hyphen_values = true)]
        value: f64,
        /// VALUE is a distance from the commanded position.
        #[arg(long, conflicts_with_all = ["additive", "velocity"])]
        relative: bool,
        /// VALUE is a distance from the target of the last move.
        #[arg(long, conflicts_with = "velocity")]
        additive: bool,
        /// VALUE is a velocity (velocity mode, ContinuousMotion).
        #[arg(long)]
        velocity: bool,
        /// Velocity mode: seconds at the velocity before the halt.
        #[arg(long = "for", default_value_t = 1.0)]
        hold: f64,
        #[command(flatten)]
        limits: MoveArgs,
        /// Power the axis on first if it is disabled.
        #[arg(long)]
        enable: bool,
        #[arg(long)]
        json: bool,
    },
    /// Jog at a signed velocity with the axis's jog limits, for --for seconds (the button
    /// held), then release (a halt at the jog deceleration).
    Jog {
        axis: usize,
        #[arg(allow_hyphen_values = true)]
        velocity: f64,
        /// Seconds the button is held.
        #[arg(long = "for", default_value_t = 1.0)]
        hold: f64,
        /// Power the axis on first if it is disabled.
        #[arg(long)]
        enable: bool,
        #[arg(long)]
        json: bool,
    },
    /// MC_Home with the axis's homing settings (CiA 402 methods), waited for.
    Home {
        axis: usize,
        /// What the home point reads (PLCopen's Position; plus the configured home offset).
        #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
        position: f64,
        /// The CiA 402 method (1-14, 17-30, 33, 34, 35, 37; -1..-4 hard stops) instead of the
        /// configured one.
        #[arg(long, allow_negative_numbers = true)]
        method: Option<i32>,
        /// Power the axis on first if it is disabled.
        #[arg(long)]
        enable: bool,
        #[arg(long)]
        json: bool,
    },
    /// MC_SetOverride: the axis's velocity factor, 0 to 2 (0 % to 200 %). It stays on the card
    /// for the moves that follow, whoever commands them.
    Override {
        axis: usize,
        #[arg(allow_hyphen_values = true)]
        factor: f64,
    },
    /// Run a G-code program (RS274/NGC subset: G0-G4, G17-G19, G20/G21, G90/G91, F,
    /// M62-M65) on group 0 over axes 0, 1, 2 through the card's path buffer, with corner
    /// blending, and report the path time, the peak axis velocity, acceleration and jerk over
    /// their limits, the largest deviation from the programmed path (mm) and the exact stops.
    /// On `--card sim` the card is stepped by mcctl and every tick is measured.
    Run {
        /// The program.
        file: std::path::PathBuf,
        /// Corner tolerance, mm (0: exact stop at every corner).
        #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
        tolerance: f64,
        /// The largest feed, mm/s (also the rapid feed).
        #[arg(long, default_value_t = 100.0, allow_negative_numbers = true)]
        feed_limit: f64,
        /// Every axis's velocity limit, mm/s (one value, or X,Y,Z).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "100",
            allow_negative_numbers = true
        )]
        vmax: Vec<f64>,
        /// Every axis's acceleration limit, mm/s² (one value, or X,Y,Z).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "1000",
            allow_negative_numbers = true
        )]
        amax: Vec<f64>,
        /// Every axis's jerk limit, mm/s³ (one value, or X,Y,Z).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "100000",
            allow_negative_numbers = true
        )]
        jmax: Vec<f64>,
        /// Counts per mm.
        #[arg(long, default_value_t = 1000.0)]
        scale: f64,
        /// Send every line as it is: no runs of short lines sent as the curve they sample
        /// (see the SDK's chord fitting).
        #[arg(long)]
        no_chord_fit: bool,
        #[arg(long)]
        json: bool,
    },
    /// The tuning page: a local web server for one axis with live plots of the scope stream
    /// (command, actual, following error, DAC), step and move tests with their rise time,
    /// overshoot, settling time and peak following error, and the FFPIV / PD+ gains, editable
    /// and applied to the card. Prints `listening on http://ADDR/#token=TOKEN` once open (the
    /// address to open: the page takes the token from it, and every API request needs it);
    /// runs until interrupted. Answers only requests addressed to ADDR or localhost, and only
    /// its own page.
    Serve {
        /// Address and port to listen on (port 0: any free port). An address beyond loopback
        /// (0.0.0.0, a network interface's) makes the page reachable from the network, without
        /// TLS: mcctl warns so on stderr.
        #[arg(long, default_value = "127.0.0.1:8080")]
        listen: std::net::SocketAddr,
        /// The token the API requires (16 to 256 characters of A-Z a-z 0-9 - . _ ~), e.g. to
        /// keep one address across restarts; by default a new one of 128 random bits each
        /// run. Other users of this machine can read a command line: prefer the default.
        #[arg(long, value_name = "TOKEN")]
        token: Option<mcctl::serve::Token>,
        /// The axis the page tunes.
        #[arg(long, default_value_t = 0)]
        axis: usize,
    },
    /// MC_Halt: decelerate to rest.
    Halt {
        axis: usize,
        #[arg(long, default_value_t = 1e6)]
        dmax: f64,
        #[arg(long, default_value_t = 5e7)]
        jmax: f64,
    },
}

/// Open the card, run `f` on it and close it. A signal (SIGINT, SIGTERM, SIGHUP: see
/// `cli::interrupt`) ends `f`'s waits; the close then ends the session cleanly, and the card
/// halts what mcctl started.
fn with_card<T>(
    uri: &str,
    f: impl FnOnce(&Card) -> motioncard_sdk::Result<T>,
) -> motioncard_sdk::Result<T> {
    let card = Card::open(uri)?;
    cli::interrupt::watch(Some(&card));
    let out = match cli::interrupt::check() {
        Ok(()) => f(&card),
        Err(e) => Err(e), // the signal came while the card was being opened
    };
    let closed = card.close();
    cli::interrupt::watch(None);
    out.and_then(|o| closed.map(|()| o))
}

/// mcctl was interrupted by a signal: it closed the card (or never opened it) and says so;
/// the exit status is 128 + the signal's number, as a shell reports a process the signal
/// ended.
fn interrupted() -> Option<ExitCode> {
    let s = cli::interrupt::signal()?;
    eprintln!("mcctl: {s}: stopped; the card halted what mcctl started and the session closed");
    Some(ExitCode::from(128u8.wrapping_add(s as i32 as u8)))
}

/// A subcommand that talks to the card: exit status 1 with the SDK's message on an error.
fn on_card(uri: &str, f: impl FnOnce(&Card) -> motioncard_sdk::Result<String>) -> ExitCode {
    let r = with_card(uri, f);
    if let Some(code) = interrupted() {
        return code;
    }
    match r {
        Ok(text) => {
            print!("{text}");
            if !text.is_empty() && !text.ends_with('\n') {
                println!();
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// `mcctl config`: as [`on_card`], but a file that does not parse or validate (or cannot be
/// read or written) is exit status 2, a bad argument, and `diff` exits 1 when the file and the
/// card differ.
fn config(uri: &str, action: ConfigCmd) -> ExitCode {
    let r = with_card(uri, |card| match &action {
        ConfigCmd::Save { file } => cli::config_save(card, file).map(|t| (t, false)),
        ConfigCmd::Load { file, json } => cli::config_load(card, file, *json).map(|t| (t, false)),
        ConfigCmd::Diff { file, json } => cli::config_diff(card, file, *json),
    });
    if let Some(code) = interrupted() {
        return code;
    }
    match r {
        Ok((text, differ)) => {
            print!("{text}");
            if differ {
                ExitCode::from(1)
            } else {
                ExitCode::SUCCESS
            }
        }
        // A file that does not parse or validate, or cannot be read or written, is a bad
        // argument.
        Err(e)
            if matches!(
                e.kind(),
                motioncard_sdk::ErrorKind::ConfigFile | motioncard_sdk::ErrorKind::Io
            ) =>
        {
            bad(e.to_string())
        }
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// A 32-bit word in decimal or 0x hex.
fn parse_word(s: &str) -> Result<u32, String> {
    let r = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(h) => u32::from_str_radix(h, 16),
        None => s.parse::<u32>(),
    };
    r.map_err(|e| format!("`{s}` is not a 32-bit word: {e}"))
}

/// A gear ratio `NUM/DEN` of integers.
fn parse_ratio(s: &str) -> Result<(i64, i64), String> {
    let (n, d) = s.split_once('/').unwrap_or((s, "1"));
    match (n.trim().parse(), d.trim().parse()) {
        (Ok(n), Ok(d)) => Ok((n, d)),
        _ => Err(format!("`{s}` is not a ratio NUM/DEN of integers")),
    }
}

/// The coupling of `mcctl gear` and `mcctl cam`: the master's move needs a master axis.
fn coupling(
    slave: usize,
    master: Master,
    sync: &SyncArgs,
    t: &TravelArgs,
) -> Result<Coupling, String> {
    let axis = match master {
        Master::Commanded(a) | Master::Actual(a) => Some(a),
        Master::Aux(_) => None,
    };
    let travel = match (axis, t.target) {
        (Some(a), _) => t.travel(a),
        (None, None) => None,
        (None, Some(_)) => {
            return Err("--move needs a master axis, not an auxiliary encoder".into())
        }
    };
    Ok(Coupling {
        slave,
        master,
        limits: SyncLimits::new(sync.slave_vmax, sync.slave_amax, sync.slave_jmax),
        travel,
        hold: t.hold()?,
        enable: t.enable,
    })
}

/// Power on `axes` that are disabled, when asked.
fn enable_all(card: &Card, enable: bool, axes: &[usize]) -> motioncard_sdk::Result<()> {
    if enable {
        for &a in axes {
            cli::enable_if_needed(card, a)?;
        }
    }
    Ok(())
}

fn bad(msg: String) -> ExitCode {
    eprintln!("mcctl: {msg}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let cli = Cli::parse(); // clap exits with status 2 on malformed arguments
    let uri = cli.card.as_str();
    // SIGINT, SIGTERM and SIGHUP close the card cleanly (cli::interrupt), before any thread
    // starts. Not for what opens no card of the user's (`plan`, `replay`, `run` on its own
    // stepped `sim`), nor for `serve`, whose server takes them itself and then closes.
    let own_card = match &cli.command {
        Cmd::Plan { .. } | Cmd::Replay { .. } | Cmd::Serve { .. } => false,
        Cmd::Run { .. } => uri != "sim",
        _ => true,
    };
    if own_card {
        if let Err(e) = cli::interrupt::install() {
            eprintln!("mcctl: {e}");
            return ExitCode::from(1);
        }
    }
    match cli.command {
        Cmd::Status {
            axis,
            watch,
            interval,
            count,
            json,
        } => {
            if !watch {
                return on_card(uri, |c| cli::status(c, axis, json));
            }
            if !(interval.is_finite() && interval > 0.0) {
                return bad(format!(
                    "--interval must be a number of seconds > 0, got {interval}"
                ));
            }
            let every = Duration::from_secs_f64(interval);
            on_card(uri, |c| cli::watch(c, axis, json, every, count))
        }
        Cmd::Info { json } => on_card(uri, |c| cli::info(c, json)),
        Cmd::Scope {
            mut channels,
            samples,
            pre,
            divider,
            trigger,
            axis,
            csv,
            svg,
            timeout,
            travel,
            json,
        } => {
            if channels.is_empty() {
                use motioncard_sdk::{Signal, Source};
                channels = [Signal::CmdPos, Signal::ActPos, Signal::Ferr, Signal::Dac]
                    .map(|s| Source::axis(s, axis))
                    .to_vec();
            }
            if !(timeout.is_finite() && timeout > 0.0) {
                return bad(format!(
                    "--timeout must be a number of seconds > 0, got {timeout}"
                ));
            }
            let job = cli::ScopeJob {
                channels,
                divider,
                trigger,
                pre_trigger: pre,
                samples,
                travel: travel.travel(axis),
                csv,
                svg,
                timeout: Duration::from_secs_f64(timeout),
            };
            on_card(uri, |c| {
                enable_all(c, travel.enable, &[axis])?;
                cli::scope(c, &job, json)
            })
        }
        Cmd::Replay { file, json } => {
            if uri != "sim" {
                return bad(format!(
                    "replay runs against an emulated card (--card sim), not {uri}"
                ));
            }
            match motioncard_sdk::replay(&file) {
                Ok(r) => {
                    println!("{}", cli::replay_report(&r, json));
                    if r.difference.is_some() {
                        ExitCode::from(1)
                    } else {
                        ExitCode::SUCCESS
                    }
                }
                Err(e @ motioncard_sdk::Error::BadConfig(_)) => bad(e.to_string()),
                Err(e) => {
                    eprintln!("mcctl: {e}");
                    ExitCode::from(1)
                }
            }
        }
        Cmd::Enable { axes } => on_card(uri, |c| cli::power(c, &axes, true)),
        Cmd::Disable { axes } => on_card(uri, |c| cli::power(c, &axes, false)),
        Cmd::Stop {
            axis,
            dmax,
            jmax,
            hold,
        } => on_card(uri, |c| cli::stop(c, axis, dmax, jmax, hold)),
        Cmd::Reset { axes, faults } => on_card(uri, |c| {
            let axes = if axes.is_empty() {
                // Every axis that needs it.
                let all: Vec<usize> = (0..c.info().axes).collect();
                let st = c.statuses(&all)?;
                all.into_iter()
                    .zip(st)
                    .filter(|(_, s)| s.state == motioncard_sdk::AxisState::ErrorStop)
                    .map(|(a, _)| a)
                    .collect()
            } else {
                axes
            };
            cli::reset(c, &axes, faults)
        }),
        Cmd::Config { action } => config(uri, action),
        Cmd::Io { set_outputs, json } => {
            let set = set_outputs.map(|v| (v[0], v[1]));
            on_card(uri, |c| cli::io(c, set, json))
        }
        Cmd::Compare {
            axis,
            output,
            channel,
            at,
            series,
            table,
            direction,
            pulse_us,
            travel,
            json,
        } => {
            let positions = match (at, series, table) {
                (Some(p), None, None) => ComparePositions::At(p),
                (None, Some(v), None) => match v[..] {
                    [start, pitch, count]
                        if count >= 1.0 && count.fract() == 0.0 && count <= u32::MAX as f64 =>
                    {
                        ComparePositions::Series {
                            start,
                            pitch,
                            count: count as u32,
                        }
                    }
                    _ => {
                        return bad(format!(
                        "--series takes START,PITCH,COUNT (COUNT a whole number >= 1), got {v:?}"
                    ))
                    }
                },
                (None, None, Some(f)) => match cli::table_positions(&f, direction.into()) {
                    Ok(_) => ComparePositions::Table(f),
                    Err(e) => return bad(format!("{}: {e}", f.display())),
                },
                _ => return bad("give exactly one of --at, --series and --table".into()),
            };
            let hold = match travel.hold() {
                Ok(h) => h,
                Err(m) => return bad(m),
            };
            let job = cli::CompareJob {
                axis,
                channel,
                output,
                pulse_us,
                direction: direction.into(),
                positions,
                travel: travel.travel(axis),
                hold,
                enable: travel.enable,
            };
            on_card(uri, |c| cli::compare(c, &job, json))
        }
        Cmd::Probe {
            axis,
            channel,
            input,
            edge,
            continuous,
            window,
            travel,
            json,
        } => {
            let hold = match travel.hold() {
                Ok(h) => h,
                Err(m) => return bad(m),
            };
            let job = cli::ProbeJob {
                axis,
                channel,
                trigger: ProbeTrigger {
                    input,
                    rising: !matches!(edge, EdgeArg::Falling),
                    falling: !matches!(edge, EdgeArg::Rising),
                    continuous,
                    window: window.map(|w| (w[0], w[1])),
                },
                travel: travel.travel(axis),
                hold,
                enable: travel.enable,
            };
            on_card(uri, |c| cli::probe(c, &job, json))
        }
        Cmd::Gear {
            slave,
            master,
            ratio,
            sync,
            travel,
            json,
        } => {
            let c = match coupling(slave, master, &sync, &travel) {
                Ok(c) => c,
                Err(m) => return bad(m),
            };
            on_card(uri, |card| cli::gear(card, &c, ratio.0, ratio.1, json))
        }
        Cmd::Cam {
            slave,
            file,
            master,
            table,
            cubic,
            periodic,
            master_offset,
            slave_offset,
            master_scale,
            slave_scale,
            relative,
            sync,
            travel,
            json,
        } => {
            let c = match coupling(slave, master, &sync, &travel) {
                Ok(c) => c,
                Err(m) => return bad(m),
            };
            let rows = std::fs::read_to_string(&file)
                .map_err(|e| e.to_string())
                .and_then(|t| cli::number_rows(&t, 2..=2, "master, slave"));
            let points = match rows {
                Ok(r) => r.into_iter().map(|v| (v[0], v[1])).collect(),
                Err(e) => return bad(format!("{}: {e}", file.display())),
            };
            let job = cli::CamJob {
                points,
                cubic,
                periodic,
                settings: CamSettings {
                    table,
                    master_offset,
                    slave_offset,
                    master_scale,
                    slave_scale,
                    relative,
                },
            };
            on_card(uri, |card| cli::cam(card, &c, &job, json))
        }
        Cmd::Pvt {
            axis,
            file,
            pt,
            vmax,
            amax,
            enable,
            json,
        } => {
            let file = match cli::pvt_file(&file) {
                Ok(f) => f,
                Err(e) => return bad(e),
            };
            if !(vmax.is_finite() && vmax > 0.0 && amax.is_finite() && amax > 0.0) {
                return bad("--vmax and --amax must be greater than zero".into());
            }
            let mode = if pt || !file.velocities {
                motioncard_sdk::PvtMode::Pt
            } else {
                motioncard_sdk::PvtMode::Pvt
            };
            let limits = motioncard_sdk::PvtLimits {
                velocity: vmax,
                acceleration: amax,
            };
            on_card(uri, |c| {
                if enable {
                    cli::enable_if_needed(c, axis)?;
                }
                cli::pvt(c, axis, &file, mode, &limits, json)
            })
        }
        Cmd::Move {
            axis,
            value,
            relative,
            additive,
            velocity,
            hold,
            limits: l,
            enable,
            json,
        } => {
            if !(hold.is_finite() && hold >= 0.0) {
                return bad(format!(
                    "--for must be a number of seconds >= 0, got {hold}"
                ));
            }
            let cmd = if velocity {
                MoveCmd::Velocity(VelocityLimits {
                    acceleration: l.amax,
                    deceleration: l.dmax.unwrap_or(l.amax),
                    jerk: l.jmax,
                })
            } else {
                let kind = match (relative, additive) {
                    (true, _) => MoveKind::Relative,
                    (_, true) => MoveKind::Additive,
                    _ => MoveKind::Absolute,
                };
                let lim =
                    MoveLimits::new(l.vmax, l.amax, l.jmax).deceleration(l.dmax.unwrap_or(l.amax));
                MoveCmd::Position(kind, lim)
            };
            on_card(uri, |c| {
                if enable {
                    cli::enable_if_needed(c, axis)?;
                }
                cli::run_move(c, axis, value, cmd, Duration::from_secs_f64(hold), json)
            })
        }
        Cmd::Jog {
            axis,
            velocity,
            hold,
            enable,
            json,
        } => {
            if !(hold.is_finite() && hold >= 0.0) {
                return bad(format!(
                    "--for must be a number of seconds >= 0, got {hold}"
                ));
            }
            on_card(uri, |c| {
                if enable {
                    cli::enable_if_needed(c, axis)?;
                }
                cli::jog(c, axis, velocity, Duration::from_secs_f64(hold), json)
            })
        }
        Cmd::Home {
            axis,
            position,
            method,
            enable,
            json,
        } => on_card(uri, |c| {
            if enable {
                cli::enable_if_needed(c, axis)?;
            }
            cli::home(c, axis, position, method, json)
        }),
        Cmd::Override { axis, factor } => on_card(uri, |c| cli::set_override(c, axis, factor)),
        Cmd::Halt { axis, dmax, jmax } => on_card(uri, |c| cli::halt(c, axis, dmax, jmax)),
        Cmd::Serve {
            listen,
            axis,
            token,
        } => {
            let opts = mcctl::serve::Options {
                listen,
                token,
                axis,
                uri: uri.to_string(),
            };
            on_card(uri, |c| mcctl::serve::serve(c, &opts))
        }
        Cmd::Run {
            file,
            tolerance,
            feed_limit,
            vmax,
            amax,
            jmax,
            scale,
            no_chord_fit,
            json,
        } => {
            let three = |v: &[f64], what: &str| -> Result<[f64; 3], String> {
                match *v {
                    [x] if x > 0.0 && x.is_finite() => Ok([x; 3]),
                    [x, y, z] if [x, y, z].iter().all(|q| *q > 0.0 && q.is_finite()) => {
                        Ok([x, y, z])
                    }
                    _ => Err(format!("--{what}: one positive value or three (X,Y,Z)")),
                }
            };
            let limits = (|| {
                Ok::<_, String>((
                    three(&vmax, "vmax")?,
                    three(&amax, "amax")?,
                    three(&jmax, "jmax")?,
                ))
            })();
            let (vmax, amax, jmax) = match limits {
                Ok(l) => l,
                Err(m) => return bad(m),
            };
            if !(tolerance >= 0.0 && tolerance.is_finite()) {
                return bad("--tolerance must be 0 or more".into());
            }
            if !(feed_limit > 0.0 && feed_limit.is_finite() && scale > 0.0 && scale.is_finite()) {
                return bad("--feed-limit and --scale must be positive".into());
            }
            // Read as it runs; one that cannot be opened is a bad argument.
            if let Err(e) = std::fs::File::open(&file) {
                return bad(format!("{}: {e}", file.display()));
            }
            let opts = mcctl::run::RunOptions {
                tolerance,
                feed_limit,
                vmax,
                amax,
                jmax,
                scale,
                progress: !json,
                chord_fit: !no_chord_fit,
            };
            let body = |c: &Card| mcctl::run::run(c, &file, &opts, json);
            if uri == "sim" {
                // A stepped card: mcctl steps it and measures every tick.
                let card = match Card::open_sim(motioncard_sdk::SimOptions {
                    clock: motioncard_sdk::Clock::Stepped,
                    emu: Default::default(),
                }) {
                    Ok(c) => c,
                    Err(e) => {
                        eprintln!("mcctl: {e}");
                        return ExitCode::from(1);
                    }
                };
                match body(&card) {
                    Ok(t) => {
                        println!("{t}");
                        ExitCode::SUCCESS
                    }
                    Err(e) => {
                        eprintln!("mcctl: {e}");
                        ExitCode::from(1)
                    }
                }
            } else {
                on_card(uri, body)
            }
        }
        Cmd::Plan {
            distance,
            vmax,
            amax,
            jmax,
            dmax,
            jdec,
            v0,
            v1,
            a0,
            servo_rate,
            json,
        } => {
            let dmax = dmax.unwrap_or(amax);
            let jdec = jdec.unwrap_or(jmax);
            let named = [
                ("distance", distance),
                ("--vmax", vmax),
                ("--amax", amax),
                ("--jmax", jmax),
                ("--dmax", dmax),
                ("--jdec", jdec),
                ("--v0", v0),
                ("--v1", v1),
            ];
            for (what, v) in named {
                if !v.is_finite() {
                    return bad(format!("{what} must be a finite number, got {v}"));
                }
            }
            for (what, v) in &named[1..6] {
                if *v <= 0.0 {
                    return bad(format!("{what} must be greater than zero, got {v}"));
                }
            }
            let rates = card_emu::SERVO_RATE_MIN_HZ..=card_emu::SERVO_RATE_MAX_HZ;
            if !rates.contains(&servo_rate) {
                return bad(format!(
                    "--servo-rate must be between {} and {} Hz, got {servo_rate}",
                    rates.start(),
                    rates.end()
                ));
            }
            // The card's range for a limit of order k (1 velocity, 2 acceleration, 3 jerk):
            // from one count in the longest move to the whole position range in one tick.
            let (vel, acc, jerk) = ((1, "velocity"), (2, "acceleration"), (3, "jerk"));
            for ((what, v), (order, kind)) in named[1..6].iter().zip([vel, acc, jerk, acc, jerk]) {
                let range = card_emu::limit_range(order, servo_rate);
                if !range.contains(v) {
                    return bad(format!(
                        "{what} must be between {:e} and {:e} (the card's {kind} range at \
                         --servo-rate {servo_rate} Hz), got {v:e}",
                        range.start(),
                        range.end()
                    ));
                }
            }
            if let Some(a0) = a0 {
                if !a0.is_finite() {
                    return bad(format!("--a0 must be a finite number, got {a0}"));
                }
                if v1.abs() > vmax {
                    return bad(format!(
                        "--v1 must be between -{vmax} and --vmax ({vmax}), got {v1}"
                    ));
                }
            }
            for (what, v) in &named[6..] {
                if a0.is_some() {
                    break;
                }
                if *v < 0.0 || *v > vmax {
                    return bad(format!(
                        "{what} must be between 0 and --vmax ({vmax}), got {v}"
                    ));
                }
            }
            // The card's own bounds: it refuses a target beyond ±MAX_POSITION counts and a
            // move longer than MAX_MOVE_TIME.
            let max_pos = card_emu::MAX_POSITION;
            if distance.abs() > max_pos {
                return bad(format!(
                    "distance must be at most {max_pos} in magnitude (2^52, the card's position \
                     range in counts), got {distance}"
                ));
            }
            let lim = Limits {
                vmax,
                amax,
                dmax,
                j1: jmax,
                j3: jmax,
                j5: jdec,
                j7: jdec,
            };
            if let Some(a0) = a0 {
                let dir = if distance < 0.0 { -1.0 } else { 1.0 };
                return from_any_state(distance, v0, a0, v1, &OtgLimits::along(dir, &lim), json);
            }
            let p = match Profile::plan(0.0, distance, v0, v1, &lim) {
                Ok(p) => p,
                Err(e) => return bad(format!("no S-curve satisfies these limits: {e}")),
            };
            // The card's own check of the plan before it runs it (Profile::plan_checked).
            match p.verify_plan(0.0, distance, v0, v1, &lim) {
                Ok(()) => {}
                Err(PlanError::Infeasible) => {
                    return bad(format!(
                        "the move would take {:.6e} s; the card refuses moves longer than {} s",
                        p.duration(),
                        card_emu::MAX_MOVE_TIME
                    ))
                }
                Err(e) => {
                    return bad(format!(
                        "the card would refuse this plan ({e}: off its target, beyond a limit, \
                         backwards or shorter than |distance|/vmax)"
                    ))
                }
            }
            let phases = p.phases();
            if json {
                let j = serde_json::json!({
                    "distance": distance,
                    "duration": p.duration(),
                    "phases": phases,
                    "peak_velocity": p.peak_velocity(),
                    "peak_acceleration": p.peak_acceleration(),
                    "peak_deceleration": p.peak_deceleration(),
                    "limits": { "vmax": vmax, "amax": amax, "dmax": dmax, "jacc": jmax, "jdec": jdec, "v0": v0, "v1": v1 },
                });
                println!("{j}");
            } else {
                println!("S-curve for a distance of {distance} (v0 {v0}, v1 {v1})");
                let names = [
                    "1 jerk +J1",
                    "2 constant acc",
                    "3 jerk -J3",
                    "4 cruise",
                    "5 jerk -J5",
                    "6 constant dec",
                    "7 jerk +J7",
                ];
                for (n, t) in names.iter().zip(phases) {
                    println!("  phase {n:<16} {t:>14.9} s");
                }
                println!("  total                  {:>14.9} s", p.duration());
                println!(
                    "  peak velocity          {:>14.6} (limit {vmax})",
                    p.peak_velocity()
                );
                println!(
                    "  peak acceleration      {:>14.6} (limit {amax})",
                    p.peak_acceleration()
                );
                println!(
                    "  peak deceleration      {:>14.6} (limit {dmax})",
                    p.peak_deceleration()
                );
            }
            ExitCode::SUCCESS
        }
    }
}

/// `mcctl plan --a0 ...`: the time-optimal trajectory from `(0, v0, a0)` to `(distance, v1)`
/// (`Trajectory::to_position`, which runs the card's check on it), printed like the S-curve.
fn from_any_state(
    distance: f64,
    v0: f64,
    a0: f64,
    v1: f64,
    lim: &OtgLimits,
    json: bool,
) -> ExitCode {
    let tr = match Trajectory::to_position(0.0, v0, a0, distance, v1, lim) {
        Ok(t) => t,
        Err(e) => return bad(format!("no trajectory satisfies these limits: {e}")),
    };
    if tr.duration() > card_emu::MAX_MOVE_TIME {
        return bad(format!(
            "the move would take {:.6e} s; the card refuses moves longer than {} s",
            tr.duration(),
            card_emu::MAX_MOVE_TIME
        ));
    }
    let phases = tr.phases();
    let jerks = &tr.jerks()[..phases.len()];
    let (amin, amax) = tr.acceleration_range();
    // Each segment named by what it does: its jerk, or the acceleration it holds.
    let mut start = 0.0;
    let mut names = Vec::new();
    for (i, (t, j)) in phases.iter().zip(jerks).enumerate() {
        let acc = tr.sample(start + 0.5 * t).acc;
        start += t;
        let what = if *j > 0.0 {
            "jerk +J"
        } else if *j < 0.0 {
            "jerk -J"
        } else if acc == 0.0 {
            "cruise"
        } else {
            "constant acc"
        };
        let part = if i < tr.brake_segments() {
            "brake"
        } else {
            "phase"
        };
        names.push(format!("{part} {} {what}", i + 1));
    }
    if json {
        let j = serde_json::json!({
            "distance": distance,
            "duration": tr.duration(),
            "brake": tr.brake_duration(),
            "phases": phases,
            "jerks": jerks,
            "peak_velocity": tr.peak_velocity(),
            "peak_acceleration": amax,
            "peak_deceleration": -amin,
            "limits": { "vmax": lim.vmax, "vmin": lim.vmin, "amax": lim.amax, "amin": lim.amin, "jmax": lim.jmax, "v0": v0, "a0": a0, "v1": v1 },
        });
        println!("{j}");
    } else {
        println!(
            "Time-optimal trajectory for a distance of {distance} from any state (v0 {v0}, a0 \
             {a0}, v1 {v1})"
        );
        for (n, t) in names.iter().zip(phases) {
            println!("  {n:<22} {t:>14.9} s");
        }
        println!("  total                  {:>14.9} s", tr.duration());
        println!("  of which brake         {:>14.9} s", tr.brake_duration());
        println!(
            "  peak velocity          {:>14.6} (limits {} .. {})",
            tr.peak_velocity(),
            lim.vmin,
            lim.vmax
        );
        println!(
            "  acceleration           {:>14.6} .. {:.6} (limits {} .. {})",
            amin, amax, lim.amin, lim.amax
        );
    }
    ExitCode::SUCCESS
}
