//! The servo gains the tuning page shows and applies: FFPIV (Thinh Fig 5, `mc_ffpiv_gains`),
//! PD+ with its drive model (Yeh eq 2.12 and 2.2, `mc_axis_pdplus`) or PID + feed-forward
//! (layout 1.11, `mc_axis_pidff`), in counts, seconds and volts as the card holds them.
//!
//! `held` is the one place that finds out which gains the card holds (the card's read-back);
//! everything else (the page's GET, the base an apply changes, the answer after an apply) goes
//! through it. Applying goes through the SDK ([`crate::Axis::configure`],
//! [`crate::Axis::configure_pdplus`], [`crate::Axis::configure_pidff`]); the card checks the values and a refusal comes back as
//! the SDK's error (`BadConfig`, `NotFinite`), which the page shows as it is.

use crate::{AxisSettings, Card, PdPlusSettings, Result};
use serde::{Deserialize, Serialize};

/// FFPIV gains, as a configuration file's `[axis.N.ffpiv]` spells them.
pub use motioncard_sdk::FfpivSection as Ffpiv;
/// PD+ gains, drive model and drive limit, as a configuration file's `[axis.N.pdplus]`.
pub use motioncard_sdk::PdPlusSection as PdPlus;
/// PID+FF gains (kp, ki, kd, kvff, kaff, friction, friction_deadband, d_filter_hz), as a
/// configuration file's `[axis.N.pidff]`.
pub use motioncard_sdk::PidffSection as Pidff;

/// The servo law an axis runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Law {
    /// FFPIV.
    Ffpiv,
    /// PD+.
    Pdplus,
    /// PID + feed-forward (layout 1.11).
    Pidff,
}

/// What the page shows: the law the axis runs and its gains.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Gains {
    /// The axis.
    pub axis: usize,
    /// The law it runs.
    pub law: Law,
    /// Its FFPIV gains (held even while it runs PD+).
    pub ffpiv: Ffpiv,
    /// Its PD+ law, when it runs PD+.
    pub pdplus: Option<PdPlus>,
    /// Its PID+FF gains, when it runs PID+FF.
    pub pidff: Option<Pidff>,
    /// Where these values come from.
    pub source: &'static str,
}

/// A change the page asks for: `{"law": "ffpiv", "kp": …}` or `{"law": "pdplus", "kp": …}`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(tag = "law", rename_all = "lowercase")]
pub enum Apply {
    /// Run FFPIV with these gains (the rest of the axis's configuration unchanged).
    Ffpiv(Ffpiv),
    /// Run PD+ with these gains and drive model.
    Pdplus(PdPlus),
    /// Run PID+FF with these gains.
    Pidff(Pidff),
}

/// What the card holds for one axis, in the SDK's types.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Held {
    cfg: AxisSettings,
    pdplus: Option<PdPlusSettings>,
    pidff: Option<crate::PidffSettings>,
}

/// [`Gains::source`]: where the values shown come from.
pub const SOURCE_CARD: &str = "read back from the card";

/// The one place that finds out what the card holds for `axis`: the card's own read-back
/// (`Axis::settings`, `Axis::pdplus_settings`, layout 1.8's `MC_OP_READ_CONFIG`), so gains
/// set by another host or a configuration file are what the page shows.
fn held(card: &Card, axis: usize) -> Result<Held> {
    let ax = card.axis(axis)?;
    Ok(Held {
        cfg: ax.settings()?,
        pdplus: ax.pdplus_settings()?,
        pidff: ax.pidff_settings()?,
    })
}

/// The gains `axis` runs with.
pub fn get(card: &Card, axis: usize) -> Result<Gains> {
    let h = held(card, axis)?;
    let law = match h.cfg.servo_law {
        crate::proto::raw::MC_SERVO_PDPLUS => Law::Pdplus,
        crate::proto::raw::MC_SERVO_PIDFF => Law::Pidff,
        _ => Law::Ffpiv,
    };
    Ok(Gains {
        axis,
        law,
        ffpiv: Ffpiv::from(&h.cfg.ffpiv),
        pdplus: h.pdplus.as_ref().map(PdPlus::from),
        pidff: h.pidff.as_ref().map(Pidff::from),
        source: SOURCE_CARD,
    })
}

/// Apply `change` to `axis` (everything else in its configuration as the card holds it), and
/// answer the gains it then runs with, read back; the card's refusal is the SDK's error and
/// changes nothing.
pub fn apply(card: &Card, axis: usize, change: &Apply) -> Result<Gains> {
    let ax = card.axis(axis)?;
    let held = held(card, axis)?;
    match *change {
        Apply::Ffpiv(g) => ax.configure(&AxisSettings {
            ffpiv: g.gains(),
            ..held.cfg
        })?,
        // A PD+ law on an axis that runs FFPIV starts from an empty block: every value it
        // needs is in the change.
        Apply::Pdplus(p) => ax.configure_pdplus(&p.onto(held.pdplus.unwrap_or_default()))?,
        Apply::Pidff(p) => ax.configure_pidff(&p.block())?,
    }
    get(card, axis)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apply_requests_parse_by_law_and_refuse_unknown_fields() {
        let a: Apply = serde_json::from_str(
            r#"{"law":"ffpiv","kp":1,"ki":2,"kv":3,"kvff":1,"kaff":0.5,"vel_filter_hz":1500}"#,
        )
        .unwrap();
        assert!(matches!(a, Apply::Ffpiv(g) if g.kp == 1.0 && g.vel_filter_hz == 1500.0));
        let a: Apply = serde_json::from_str(
            r#"{"law":"pdplus","kp":1,"kd":2,"kv":3,"ka":4,"kc":5,"tau":6,"ke":7,"umax":8}"#,
        )
        .unwrap();
        assert!(matches!(a, Apply::Pdplus(p) if p.ka == 4.0 && p.umax == 8.0));
        let a: Apply = serde_json::from_str(
            r#"{"law":"pidff","kp":1,"ki":2,"kd":3,"kvff":4,"kaff":5,"friction":6,
                "friction_deadband":7,"d_filter_hz":8}"#,
        )
        .unwrap();
        assert!(matches!(a, Apply::Pidff(p) if p.kd == 3.0 && p.d_filter_hz == 8.0));
        for bad in [
            r#"{"law":"pid","kp":1}"#,
            r#"{"law":"pidff","kp":1,"ki":2,"kd":3,"kvff":4,"kaff":5,"friction":6}"#,
            r#"{"law":"ffpiv","kp":1}"#,
            r#"{"law":"ffpiv","kp":"x","ki":2,"kv":3,"kvff":1,"kaff":0.5,"vel_filter_hz":1}"#,
            r#"{"law":"ffpiv","kp":1,"ki":2,"kv":3,"kvff":1,"kaff":0.5,"vel_filter_hz":1,"kd":0}"#,
        ] {
            assert!(serde_json::from_str::<Apply>(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_cards_refusal_changes_nothing_and_an_accepted_change_is_held() {
        let card = Card::open_sim(crate::SimOptions {
            clock: crate::Clock::Stepped,
            emu: Default::default(),
        })
        .unwrap();
        let before = get(&card, 0).unwrap();
        assert_eq!(before.law, Law::Ffpiv);
        assert_eq!(before.source, SOURCE_CARD);
        assert_eq!(before.pdplus, None);
        let mut g = before.ffpiv;
        g.kp = -1.0;
        let e = apply(&card, 0, &Apply::Ffpiv(g)).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::BadConfig, "{e}");
        assert_eq!(get(&card, 0).unwrap(), before);
        g.kp = before.ffpiv.kp * 0.5;
        let after = apply(&card, 0, &Apply::Ffpiv(g)).unwrap();
        assert_eq!(after.ffpiv, g);
        // What the firmware runs with.
        let sim = card.sim().unwrap();
        let kp = sim.with_emulator(|e| e.firmware().axis(0).unwrap().config.ffpiv.kp);
        assert_eq!(kp, g.kp);
        // The rest of the configuration is untouched.
        let cfg = card.axis(0).unwrap().settings().unwrap();
        assert_eq!(cfg.dac_limit_v, AxisSettings::default().dac_limit_v);
        // PD+ from FFPIV: refused without a drive model, accepted with the die bonder's.
        let mut p = PdPlus::from(&crate::die_bonder_pdplus(0));
        let good = p;
        p.tau = 0.0;
        let e = apply(&card, 0, &Apply::Pdplus(p)).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::BadConfig, "{e}");
        assert_eq!(get(&card, 0).unwrap().law, Law::Ffpiv);
        let now = apply(&card, 0, &Apply::Pdplus(good)).unwrap();
        assert_eq!((now.law, now.pdplus), (Law::Pdplus, Some(good)));
        assert_eq!(now.ffpiv, g, "the FFPIV gains stay held");
        // PID+FF: a negative gain refused (nothing changed), the default tuning held.
        let mut q = Pidff::from(&crate::PidffSettings::default());
        let good = q;
        q.kd = -1.0;
        let e = apply(&card, 0, &Apply::Pidff(q)).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::PidffGains, "{e}");
        assert_eq!(get(&card, 0).unwrap(), now);
        let pid = apply(&card, 0, &Apply::Pidff(good)).unwrap();
        assert_eq!(
            (pid.law, pid.pidff, pid.pdplus),
            (Law::Pidff, Some(good), None)
        );
        // Back to FFPIV.
        let back = apply(&card, 0, &Apply::Ffpiv(before.ffpiv)).unwrap();
        assert_eq!(
            (back.law, back.pdplus, back.pidff),
            (Law::Ffpiv, None, None)
        );
        assert!(get(&card, 9).is_err());
    }
}
