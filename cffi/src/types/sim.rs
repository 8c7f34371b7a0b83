//! The emulated card's options (`mc_open_sim`).

#[cfg(feature = "emulator")]
use crate::result::{unknown, Failure};
#[cfg(feature = "emulator")]
use motioncard_sdk::{die_bonder_plant, Clock, EmuOptions, SimOptions};

/// Clock of an emulated card (`mc_sim_options.clock`): paced to the servo rate in real time,
/// as `mc_open("sim")`.
pub const MC_SIM_CLOCK_REAL_TIME: u32 = 0;
/// As fast as the host can compute the ticks. The card's watchdog counts card time, which then
/// runs far ahead of the library's heartbeat: raise the timeout (`mc_set_watchdog_timeout`) and
/// clear a trip (`mc_reset_faults`) before enabling axes.
pub const MC_SIM_CLOCK_FREE_RUNNING: u32 = 1;
/// Time advances only in `mc_sim_step` and in waits (as `mc_open_sim_stepped`).
pub const MC_SIM_CLOCK_STEPPED: u32 = 2;

/// Plant of an emulated card (`mc_sim_options.plant`): the default servo motor on every axis.
pub const MC_SIM_PLANT_DEFAULT: u32 = 0;
/// Yeh's die bonder (Table 1): its X plant on axis 0, its Y plant on the other axes. Pair it
/// with `mc_pdplus_settings_die_bonder` and a 1000 Hz servo rate, as in the paper.
pub const MC_SIM_PLANT_DIE_BONDER: u32 = 1;

/// How `mc_open_sim` builds an emulated card. Start from `mc_sim_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_sim_options {
    /// `MC_SIM_CLOCK_` value.
    pub clock: u32,
    /// Axes, 1..8.
    pub axes: u32,
    /// Servo rate, 1000..20000 Hz.
    pub servo_rate_hz: u32,
    /// `MC_SIM_PLANT_` value.
    pub plant: u32,
}

/// The `MC_SIM_CLOCK_` value of a clock.
#[cfg(feature = "emulator")]
pub(crate) fn clock_code(c: Clock) -> u32 {
    match c {
        Clock::RealTime => MC_SIM_CLOCK_REAL_TIME,
        Clock::FreeRunning => MC_SIM_CLOCK_FREE_RUNNING,
        Clock::Stepped => MC_SIM_CLOCK_STEPPED,
    }
}

#[cfg(feature = "emulator")]
impl mc_sim_options {
    /// The SDK's options; the axes and servo rate are checked by `Card::open_sim`.
    pub(crate) fn to_sdk(self) -> Result<SimOptions, Failure> {
        let clock = match self.clock {
            MC_SIM_CLOCK_REAL_TIME => Clock::RealTime,
            MC_SIM_CLOCK_FREE_RUNNING => Clock::FreeRunning,
            MC_SIM_CLOCK_STEPPED => Clock::Stepped,
            v => return Err(unknown("clock", v)),
        };
        let mut emu = EmuOptions::new(self.axes as usize, self.servo_rate_hz);
        match self.plant {
            MC_SIM_PLANT_DEFAULT => {}
            MC_SIM_PLANT_DIE_BONDER => {
                for (i, m) in emu.motors.iter_mut().enumerate() {
                    *m = die_bonder_plant(i.min(1));
                }
            }
            v => return Err(unknown("plant", v)),
        }
        Ok(SimOptions { clock, emu })
    }
}

#[cfg(feature = "emulator")]
impl From<SimOptions> for mc_sim_options {
    /// The clock, axes and rate of the SDK's options (the plant as `MC_SIM_PLANT_DEFAULT`).
    fn from(o: SimOptions) -> Self {
        Self {
            clock: clock_code(o.clock),
            axes: o.emu.axes as u32,
            servo_rate_hz: o.emu.servo_rate_hz,
            plant: MC_SIM_PLANT_DEFAULT,
        }
    }
}

#[cfg(all(test, feature = "emulator"))]
mod tests {
    use super::*;
    use motioncard_sdk::ErrorKind;

    #[test]
    fn sim_options_round_trip_and_unknown_values_are_refused() {
        let d = mc_sim_options::from(SimOptions::default());
        assert_eq!(
            d,
            mc_sim_options {
                clock: MC_SIM_CLOCK_REAL_TIME,
                axes: 8,
                servo_rate_hz: 10_000,
                plant: MC_SIM_PLANT_DEFAULT
            }
        );
        assert_eq!(d.to_sdk().unwrap(), SimOptions::default());
        for c in [Clock::RealTime, Clock::FreeRunning, Clock::Stepped] {
            let o = mc_sim_options {
                clock: clock_code(c),
                ..d
            };
            assert_eq!(o.to_sdk().unwrap().clock, c);
        }
        let bonder = mc_sim_options {
            plant: MC_SIM_PLANT_DIE_BONDER,
            axes: 3,
            ..d
        }
        .to_sdk()
        .unwrap();
        assert_eq!(bonder.emu.motors[0], die_bonder_plant(0));
        assert_eq!(bonder.emu.motors[1], die_bonder_plant(1));
        assert_eq!(bonder.emu.motors[7], die_bonder_plant(1));
        for bad in [
            mc_sim_options { clock: 3, ..d },
            mc_sim_options { plant: 2, ..d },
        ] {
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadConfig.code(),
                "{bad:?}"
            );
        }
    }
}
