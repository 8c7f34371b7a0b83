//! `mcctl`: the motion card from the command line, for machine builders who do not want to
//! write code.
//!
//! ```text
//! mcctl plan 100000 --vmax 200000 --amax 2e6 --jmax 1e8            # the S-curve the card plans
//! mcctl plan 100000 --vmax 2e5 --amax 2e6 --dmax 1e6 --jmax 1e8 --jdec 2e7 --json
//! mcctl plan 100000 --vmax 5e19 --amax 2e6 --jmax 1e8 --servo-rate 20000   # limits in the card's range
//! mcctl plan 100 --vmax 10 --amax 100 --jmax 1e3 --v0 -15 --a0 0     # from any state (time-optimal)
//! mcctl --card emu:bench1 info                       # firmware, layout, axes, servo rate
//! mcctl list --json                                  # every card here: name, serial, sync role
//! mcctl --card name:bench1 info                      # a card by its name (serial:N: by serial)
//! mcctl scope --move 20000 --enable --pre 100 --trigger level:0:1 --csv m.csv --svg m.svg
//! MOTIONCARD_TRACE=run.trace ./my_program && mcctl replay run.trace   # API trace, replayed
//! mcctl --card emu:bench1 status --watch             # axes and groups, live (--json: one object)
//! mcctl --card emu:bench1 enable 0 1                 # MC_Power (disable, stop, reset likewise)
//! mcctl --card emu:bench1 move 0 -25000 --vmax 1e5 --amax 1e6 --jmax 5e7 --enable
//! mcctl --card emu:bench1 move 0 20000 --velocity --for 2   # velocity mode for 2 s
//! mcctl --card emu:bench1 override 0 0.5             # 50 %
//! mcctl --card emu:bench1 home 0 --method 37 --position 100   # MC_Home (CiA 402 method)
//! mcctl --card emu:bench1 jog 0 -20000 --for 1.5     # hold the button 1.5 s, then release
//! mcctl --card emu:bench1 handwheel 0 --input 0 --ratio 10 --for 60   # aux 0 jogs axis 0, x10
//! mcctl --card emu:bench1 freq 0 --from 5 --to 1000 --points 40 --amplitude 100 --json   # Bode
//! mcctl --card emu:bench1 gantry form 0 --slaves 1 --skew-limit 200 --offsets 25   # a gantry
//! mcctl --card emu:bench1 gantry home 0              # each side homed, the bridge squared
//! mcctl --card emu:bench1 gantry status --json       # phase, skews, gains (dissolve 0 ends it)
//! mcctl --card emu:bench1 group home 0 --order "2;0,1"   # Z first, then X and Y together
//! mcctl --card emu:bench1 group status 0 --json      # state, axes, configured home order
//! mcctl --card emu:bench1 comp 0 load x-laser.csv --bound 0.02 --backlash 0.004   # pitch error
//! mcctl --card emu:bench1 comp 0 show                # the table read back (clear: off)
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
//! mcctl path-set points.txt --cards sim --split 6,6     # a 12-axis path over two cards
//! mcctl --card emu:bench1 serve --listen 127.0.0.1:8080 --axis 0   # the tuning page (open the
//!                                                    # http://…/#token=… address it prints)
//! ```
//!
//! Each subcommand is a module of `mcctl::cli` (its arguments and its `run`); this file parses
//! the command line and dispatches.
use clap::{Parser, Subcommand};
use mcctl::cli;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "mcctl", version, about = "Motion card command-line tool")]
struct Cli {
    /// The card: `sim` (an emulated card in this process), `emu:NAME` (a card-emu process),
    /// `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`, or `name:NAME` / `serial:N` (a card `mcctl list`
    /// shows).
    #[arg(long, global = true, default_value = "sim")]
    card: String,
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Card configuration files in TOML: save, load, diff (every value in the card's units).
    Config {
        #[command(subcommand)]
        action: cli::config::Action,
    },
    /// Print the seven-segment S-curve the card plans for one axis (Thinh eq 1–28): the phase
    /// durations, total time, peak velocity and acceleration. Units are the caller's (counts and
    /// seconds on the card).
    Plan(cli::plan::Args),
    /// The card's digital inputs (debounced and raw) and outputs; with --analog its analog
    /// inputs, spare DAC outputs and the path-speed output (PSO), set by --set-analog,
    /// --analog-input, --pso and --pso-off.
    Io(cli::io::Args),
    /// Stream a PT/PVT file through the axis's point buffer and wait for its end: one
    /// `time, position[, velocity]` per line (seconds from the start, the axis's units; `#`
    /// comments). Unless every line gives a velocity (or with --pt) the card estimates them
    /// (PT).
    Pvt(cli::pvt::Args),
    /// Position compare (EQU output): pulse an output as the axis crosses positions. Arms
    /// the channel, runs --move (or watches --for seconds), reports the fires and misses the
    /// card counted with the positions of its events (misses of one tick share one event: the
    /// last position), and disarms.
    Compare(cli::compare::Args),
    /// Touch probe (MC_TouchProbe): latch the axis's position at an input edge or at the
    /// encoder's index pulse. Arms, runs --move (or watches --for seconds), reports every
    /// capture, and aborts the probe (MC_AbortTrigger).
    Probe(cli::probe::Args),
    /// Electronic gearing (MC_GearIn): the slave follows the master at an integer ratio; the
    /// master runs --move (or an auxiliary encoder is watched --for seconds); then MC_GearOut
    /// and a halt. Reports both travels and the slave's error against the ratio.
    Gear(cli::gear::Args),
    /// Camming (MC_CamTableSelect, MC_CamIn): load a cam table (one `master, slave` per line),
    /// couple the slave to the master through it, run the master's --move, MC_CamOut and a halt.
    /// Reports the slave's end position against the table's.
    Cam(cli::cam::Args),
    /// The axes' state, positions, velocity, following error, queue, override and faults, and
    /// the groups' state, queues, path segment and feed.
    Status(cli::status::Args),
    /// The card's scope: a one-shot capture of up to 16 channels (every --divider-th servo
    /// tick), from a trigger with --pre samples before it, of a --move of --axis started while
    /// armed; written to --csv and --svg, summarised per channel.
    Scope(cli::scope::Args),
    /// Replay an API trace (recorded with MOTIONCARD_TRACE=FILE or Card::open_traced) against
    /// an emulated card (`--card sim`) and report the first answer or event that differs (exit
    /// status 1 when one does).
    Replay(cli::replay::Args),
    /// What the card is: firmware and layout versions, axes, groups, servo rate, capabilities.
    Info(cli::info::Args),
    /// Every card reachable from here (card-emu processes, UIO devices, PCI functions): URI,
    /// name, serial, axes, servo rate, sync role, available or busy. Opens no card.
    List(cli::list::Args),
    /// MC_Power on: enable the axes.
    Enable(cli::power::Args),
    /// MC_Power off: disable the axes.
    Disable(cli::power::Args),
    /// MC_Stop: decelerate to rest, then release the stop (the axis in Standstill again;
    /// --hold keeps it Stopping until the session ends).
    Stop(cli::stop::Args),
    /// MC_Reset: the axes out of ErrorStop; --faults first resets the card's latched safety
    /// faults (e-stop, host watchdog).
    Reset(cli::reset::Args),
    /// MC_MoveAbsolute (default), MC_MoveRelative, MC_MoveAdditive or MC_MoveVelocity, and wait
    /// until done (velocity mode: run --for seconds, then halt). The axis runs only while
    /// mcctl does: a host that leaves closes its session, and the card halts what it started.
    Move(cli::moves::Args),
    /// Jog at a signed velocity with the axis's jog limits, for --for seconds (the button
    /// held), then release (a halt at the jog deceleration).
    Jog(cli::jog::Args),
    /// Layout 1.10: an auxiliary encoder (--input) jogs the axis, --ratio encoder counts per
    /// detent (x1, x10, x100), for --for seconds, then lets go (the axis goes on to where the
    /// wheel put it). --off only lets go.
    Handwheel(cli::handwheel::Args),
    /// The frequency response measured on the card: a stepped sine on the axis's reference
    /// (closed loop) or, --plant, its servo output (plant, open loop); gain dB, phase deg,
    /// resonances.
    Freq(cli::freq::Args),
    /// Layout 1.10: gantry axes (a master and its slaves, one logical axis): form, home (each
    /// side homed, the bridge squared to its offsets), status, dissolve. Lengths in the
    /// master's user units.
    Gantry {
        #[command(subcommand)]
        action: cli::gantry::Action,
    },
    /// Layout 1.11: axes groups: home (MC_GroupHome, in stages: --order "2;0,1" homes the
    /// group's Z, then X and Y together; else the group's configured order), status.
    Group {
        #[command(subcommand)]
        action: cli::group::Action,
    },
    /// Layout 1.9: an axis's leadscrew pitch-error and backlash compensation: load a table
    /// file (`position, correction[, correction_negative]` a line, user units; --errors: the
    /// columns are measured errors), show the table the card holds, clear it.
    Comp(cli::comp::Args),
    /// MC_Home with the axis's homing settings (CiA 402 methods), waited for.
    Home(cli::home::Args),
    /// MC_SetOverride: the axis's velocity factor, 0 to 2 (0 % to 200 %). It stays on the card
    /// for the moves that follow, whoever commands them.
    Override(cli::set_override::Args),
    /// Read a G-code program (RS274/NGC as LinuxCNC documents it for milling) without a card
    /// and print its canonical operations in machine coordinates (--json: one object a line,
    /// with `line`, `kind`, and for motions `end` and `length`).
    Gcode(cli::gcode::Args),
    /// Run a G-code program (RS274/NGC, as `mcctl gcode` reads it) on group 0 over axes 0, 1,
    /// 2 (X, Y, Z) through the card's path buffer, with corner blending, and report the path time, the peak axis velocity, acceleration and jerk over
    /// their limits, the largest deviation from the programmed path (mm) and the exact stops.
    /// On `--card sim` the card is stepped by mcctl and every tick is measured.
    Run(cli::run::Args),
    /// The tuning page: a local web server for one axis with live plots of the scope stream
    /// (command, actual, following error, DAC), step and move tests with their rise time,
    /// overshoot, settling time and peak following error, and the FFPIV / PD+ gains, editable
    /// and applied to the card. Prints `listening on http://ADDR/#token=TOKEN` once open (the
    /// address to open: the page takes the token from it, and every API request needs it);
    /// runs until interrupted. Answers only requests addressed to ADDR or localhost, and only
    /// its own page.
    Serve(cli::serve::Args),
    /// MC_Halt: decelerate to rest.
    Halt(cli::halt::Args),
    /// Layout 1.14: a path across the cards of one sync bus (--cards, the master first; `sim`:
    /// stepped emulated cards here), each card's group 0 over its first --split axes, the
    /// path's dimensions those axes in order (up to 16). The file: a line of N numbers a point
    /// (a line to it), or `dwell SECONDS`. Released on one tick on every card; prints where
    /// every card's axes ended.
    PathSet(cli::path_set::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse(); // clap exits with status 2 on malformed arguments and bad values
    let uri = cli.card.as_str();
    // SIGINT, SIGTERM and SIGHUP close the card cleanly (cli::interrupt), before any thread
    // starts. Not for what opens no card of the user's (`plan`, `replay`, `run` on its own
    // stepped `sim`), nor for `serve`, whose server takes them itself and then closes.
    let own_card = match &cli.command {
        Cmd::Plan(_) | Cmd::Replay(_) | Cmd::Serve(_) | Cmd::Gcode(_) | Cmd::List(_) => false,
        Cmd::Run(_) => uri != "sim",
        _ => true,
    };
    if own_card {
        if let Err(e) = cli::interrupt::install() {
            eprintln!("mcctl: {e}");
            return ExitCode::from(1);
        }
    }
    match cli.command {
        Cmd::Config { action } => cli::config::run(uri, action),
        Cmd::Plan(a) => cli::plan::run(a),
        Cmd::Io(a) => cli::io::run(uri, a),
        Cmd::Pvt(a) => cli::pvt::run(uri, a),
        Cmd::Compare(a) => cli::compare::run(uri, a),
        Cmd::Probe(a) => cli::probe::run(uri, a),
        Cmd::Gear(a) => cli::gear::run(uri, a),
        Cmd::Cam(a) => cli::cam::run(uri, a),
        Cmd::Status(a) => cli::status::run(uri, a),
        Cmd::Scope(a) => cli::scope::run(uri, a),
        Cmd::Replay(a) => cli::replay::run(uri, a),
        Cmd::Info(a) => cli::info::run(uri, a),
        Cmd::List(a) => cli::list::run(a),
        Cmd::Enable(a) => cli::power::run(uri, a, true),
        Cmd::Disable(a) => cli::power::run(uri, a, false),
        Cmd::Stop(a) => cli::stop::run(uri, a),
        Cmd::Reset(a) => cli::reset::run(uri, a),
        Cmd::Move(a) => cli::moves::run(uri, a),
        Cmd::Jog(a) => cli::jog::run(uri, a),
        Cmd::Handwheel(a) => cli::handwheel::run(uri, a),
        Cmd::Freq(a) => cli::freq::run(uri, a),
        Cmd::Gantry { action } => cli::gantry::run(uri, action),
        Cmd::Group { action } => cli::group::run(uri, action),
        Cmd::Comp(a) => cli::comp::run(uri, a),
        Cmd::Home(a) => cli::home::run(uri, a),
        Cmd::Override(a) => cli::set_override::run(uri, a),
        Cmd::Run(a) => cli::run::run(uri, a),
        Cmd::Gcode(a) => cli::gcode::run(a),
        Cmd::Serve(a) => cli::serve::run(uri, a),
        Cmd::Halt(a) => cli::halt::run(uri, a),
        Cmd::PathSet(a) => cli::path_set::run(a),
    }
}
