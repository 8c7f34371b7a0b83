//! The servo output's filters the tuning page lists, adds, edits and clears (layout 1.11): the
//! axis's [`BIQUADS`](crate::BIQUADS) slots as a configuration file's `[axis.N.biquad.K]`
//! spells them (`kind` and the keys of that kind), each with the coefficients the card
//! designed at its servo rate. As with the gains, everything shown is the card's read-back
//! ([`crate::Axis::servo_filters`]); a change goes through the SDK
//! ([`crate::Axis::set_servo_filter`], [`crate::Axis::clear_servo_filter`]) and the card's
//! refusal (`FilterFreq`, `FilterParam`, `FilterUnstable`, `FilterKind`, `NotFinite`) comes back
//! as the SDK's error, nothing changed.

use crate::{BiquadSection, Card, Error, Result};
use serde::{Deserialize, Serialize};

/// One slot as the page shows it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Slot {
    /// The slot, 0..4.
    pub slot: usize,
    /// The filter as set (`kind = "none"`: empty).
    pub filter: BiquadSection,
    /// The card's coefficients b0, b1, b2, a1, a2 (empty slot: none).
    pub coeffs: Option<[f64; 5]>,
}

/// The axis's filters, slot by slot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Filters {
    /// The axis.
    pub axis: usize,
    /// The servo rate the card designed them at, Hz (Nyquist: half of it).
    pub servo_rate_hz: u32,
    /// Every slot, in order.
    pub slots: Vec<Slot>,
}

/// A change the page asks for: `{"slot": 1, "filter": {"kind": "notch", "freq_hz": 24,
/// "damping": 0.2, "depth_db": -20}}`; `{"kind": "none"}` clears the slot.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Change {
    /// The slot.
    pub slot: usize,
    /// The filter.
    pub filter: BiquadSection,
}

/// Why a change was not made.
#[derive(Debug)]
pub enum FilterError {
    /// The request names keys its kind does not take, or lacks one (nothing sent to the card).
    Request(String),
    /// The card refused it, or failed.
    Card(Error),
}

impl From<Error> for FilterError {
    fn from(e: Error) -> Self {
        Self::Card(e)
    }
}

/// The filters `axis` holds, read back from the card.
pub fn get(card: &Card, axis: usize) -> Result<Filters> {
    let held = card.axis(axis)?.servo_filters()?;
    Ok(Filters {
        axis,
        servo_rate_hz: card.servo_rate()?,
        slots: held
            .iter()
            .enumerate()
            .map(|(slot, f)| Slot {
                slot,
                filter: BiquadSection::from_spec(f.as_ref().map(|f| &f.spec)),
                coeffs: f.map(|f| f.coeffs),
            })
            .collect(),
    })
}

/// Set or clear one slot of `axis`, and answer the filters then held.
pub fn apply(
    card: &Card,
    axis: usize,
    change: &Change,
) -> std::result::Result<Filters, FilterError> {
    let f = &change.filter;
    if let Some((key, needed, _)) = f.keys().into_iter().find(|(_, n, p)| n != p) {
        let kind = serde_json::to_value(f.kind).unwrap_or_default();
        return Err(FilterError::Request(if needed {
            format!("a filter of kind {kind} needs `{key}`")
        } else {
            format!("`{key}` is not a key of a filter of kind {kind}")
        }));
    }
    let ax = card.axis(axis)?;
    match f.spec() {
        Some(spec) => ax.set_servo_filter(change.slot, &spec)?,
        None => ax.clear_servo_filter(change.slot)?,
    }
    Ok(get(card, axis)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BiquadName;

    fn card() -> Card {
        Card::open_sim(crate::SimOptions {
            clock: crate::Clock::Stepped,
            emu: Default::default(),
        })
        .unwrap()
    }

    #[test]
    fn a_filter_is_set_edited_refused_and_cleared_as_the_card_holds_it() {
        let card = card();
        let empty = get(&card, 0).unwrap();
        assert_eq!(empty.slots.len(), crate::BIQUADS);
        assert!(empty
            .slots
            .iter()
            .all(|s| s.filter.kind == BiquadName::None && s.coeffs.is_none()));
        let notch: Change = serde_json::from_str(
            r#"{"slot":1,"filter":{"kind":"notch","freq_hz":24,"damping":0.2,"depth_db":-20}}"#,
        )
        .unwrap();
        let now = apply(&card, 0, &notch).unwrap();
        assert_eq!(now.slots[1].filter, notch.filter);
        let c = now.slots[1].coeffs.unwrap();
        // A notch passes DC: (b0 + b1 + b2) / (1 + a1 + a2) = 1.
        assert!(((c[0] + c[1] + c[2]) / (1.0 + c[3] + c[4]) - 1.0).abs() < 1e-9);
        // Edited: the centre moved.
        let mut moved = notch;
        moved.filter.freq_hz = Some(30.0);
        assert_eq!(
            apply(&card, 0, &moved).unwrap().slots[1].filter.freq_hz,
            Some(30.0)
        );
        // Above Nyquist: the card's refusal, nothing changed.
        let mut high = moved;
        high.filter.freq_hz = Some(6000.0);
        match apply(&card, 0, &high) {
            Err(FilterError::Card(e)) => assert_eq!(e.kind(), crate::ErrorKind::FilterFreq),
            other => panic!("{other:?}"),
        }
        assert_eq!(get(&card, 0).unwrap().slots[1].filter, moved.filter);
        // A key its kind does not take: refused before the card.
        let mut extra = moved;
        extra.filter.freq2_hz = Some(1.0);
        assert!(
            matches!(apply(&card, 0, &extra), Err(FilterError::Request(m)) if m.contains("freq2_hz"))
        );
        // Cleared.
        let clear: Change = serde_json::from_str(r#"{"slot":1,"filter":{"kind":"none"}}"#).unwrap();
        assert_eq!(apply(&card, 0, &clear).unwrap(), empty);
        assert!(serde_json::from_str::<Change>(r#"{"slot":1,"filter":{"kind":"comb"}}"#).is_err());
    }
}
