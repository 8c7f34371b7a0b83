//! A rotary knife on the emulated card: a conveyor (the card's auxiliary encoder 0) carries a
//! web; the knife axis turns once per sheet on a periodic cubic cam so that at the cut its
//! blade moves with the web, and between cuts it speeds up or slows down to make the sheet
//! length. Prints, at each cut, the knife's velocity against the web's and how far the knife
//! is from the table; the peaks of a cycle.
//!
//! `cargo run --release --example rotary_knife [-- --sheet 20000 --sync 0.8]`
use clap::Parser;
use motioncard_sdk::{CamSettings, Card, Clock, EmuOptions, Master, SimOptions, SyncLimits};
use std::f64::consts::TAU;
use std::time::Duration;

/// A rotary knife cammed to a conveyor.
#[derive(Parser)]
struct Args {
    /// Sheet length, conveyor counts.
    #[arg(long, default_value_t = 20_000.0)]
    sheet: f64,
    /// Knife counts per turn.
    #[arg(long, default_value_t = 10_000.0)]
    turn: f64,
    /// Knife counts per conveyor count at the cut (the blade's speed matches the web's).
    #[arg(long, default_value_t = 0.8)]
    sync: f64,
    /// Conveyor speed, counts/s.
    #[arg(long, default_value_t = 20_000.0)]
    speed: f64,
    /// Sheets to cut.
    #[arg(long, default_value_t = 3)]
    sheets: u32,
}

/// One cycle of the knife: s(m) = turn·m/sheet + c·sin(2πm/sheet), c such that ds/dm = sync at
/// the cut (m = 0); 64 segments, the first and last point the same point of the cycle.
fn knife_table(a: &Args) -> Vec<(f64, f64)> {
    let c = (a.sync - a.turn / a.sheet) * a.sheet / TAU;
    (0..=64)
        .map(|i| {
            let m = a.sheet * i as f64 / 64.0;
            (m, a.turn / a.sheet * m + c * (TAU * m / a.sheet).sin())
        })
        .collect()
}

fn main() -> motioncard_sdk::Result<()> {
    let a = Args::parse();
    let rate = 10_000;
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu: EmuOptions::new(1, rate),
    })?;
    let sim = card.sim().expect("a stepped card");
    let knife = card.axis(0)?;
    knife.enable()?;
    let table = knife_table(&a);
    card.load_cam_table(0, &table, true, true)?;
    sim.set_aux_velocity(0, a.speed)?;
    sim.step(100);
    // The cam's master origin: the conveyor's count now, so the first cut is one sheet on.
    let origin = card.aux_encoder(0)? as f64 + a.sheet;
    // One sheet before the first cut the table reads −turn: the slave offset puts the knife
    // where it stands (0), so engaging moves it only to match the web's speed.
    let cam = CamSettings {
        master_offset: origin,
        slave_offset: a.turn,
        ..CamSettings::new(0)
    };
    let lim = SyncLimits::new(5.0 * a.speed, 2e6, 2e8);
    knife
        .cam_in(Master::Aux(0), &cam, &lim)?
        .wait_in_sync(Duration::from_secs(10))?;
    println!(
        "rotary knife: sheet {} conveyor counts, {} knife counts a turn, conveyor {} counts/s, \
         blade at {} × the web at the cut",
        a.sheet, a.turn, a.speed, a.sync
    );
    let (mut vmax, mut amax) = (0.0f64, 0.0f64);
    let mut next_cut = origin + a.sheet;
    let mut cuts = 0;
    let ticks = (a.sheets as f64 + 1.5) * a.sheet / a.speed * rate as f64;
    for _ in 0..ticks as u64 {
        sim.step(1);
        let st = knife.status()?;
        vmax = vmax.max(st.command_velocity.abs());
        amax = amax.max(st.command_acceleration.abs());
        let m = card.aux_encoder(0)? as f64;
        if m >= next_cut && cuts < a.sheets {
            cuts += 1;
            println!(
                "cut {cuts}: conveyor at {m}, knife at {:.3} counts moving {:.1} counts/s \
                 (web × sync: {:.1}), following error {:.3}",
                st.command_position,
                st.command_velocity,
                a.speed * a.sync,
                st.following_error
            );
            next_cut += a.sheet;
        }
    }
    println!("peaks over the run: {vmax:.1} counts/s, {amax:.1} counts/s²");
    knife.cam_out()?.wait_in_velocity(Duration::from_secs(10))?;
    knife.halt(2e6, 2e8)?.wait(Duration::from_secs(10))?;
    card.close()
}
