//! `motioncard._motioncard`: the SDK (`motioncard_sdk`) for Python. The package `motioncard`
//! (python/motioncard/__init__.py) re-exports it and adds what is plain Python: the enums
//! built from the lists exported here, the asyncio functions.
//!
//! Every call that waits releases the GIL and waits in slices of at most [`wait::SLICE`], checking
//! for signals between them, so Ctrl-C ends a wait with `KeyboardInterrupt`.
use pyo3::prelude::*;

mod card;
mod cardset;
mod errors;
mod group;
mod io;
mod machine;
mod motion;
mod names;
mod path;
mod safety;
mod scope;
mod servo;
mod timed;
mod trace;
mod wait;

use names::members;

#[pymodule]
fn _motioncard(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use motioncard_sdk as sdk;
    errors::register(m)?;
    m.add_function(wrap_pyfunction!(errors::_raise_kind, m)?)?;
    m.add(
        "AXIS_STATES",
        members(sdk::AxisState::ALL, |e| e as u32 as i64),
    )?;
    m.add(
        "GROUP_STATES",
        members(sdk::GroupState::ALL, |e| e as u32 as i64),
    )?;
    m.add(
        "EVENT_KINDS",
        members(sdk::EventKind::ALL, |e| e as u16 as i64),
    )?;
    m.add("SIGNALS", members(sdk::Signal::ALL, |e| e as u32 as i64))?;
    m.add(
        "STOP_CATEGORIES",
        members(sdk::StopCategory::ALL, |e| e as u32 as i64),
    )?;
    m.add(
        "STOP_REASONS",
        members(sdk::StopReason::ALL, |e| e as u32 as i64),
    )?;
    m.add("SCOPE_CHANNELS", sdk::SCOPE_CHANNELS)?;
    m.add("INPUTS", sdk::INPUTS)?;
    m.add("NURBS_MAX_CTRL", sdk::NURBS_MAX_CTRL)?;
    m.add("ANALOG_INPUTS", sdk::ANALOG_INPUTS)?;
    m.add("ADC_LSB", sdk::ADC_LSB)?;
    m.add("COMPARE_FIRED", sdk::COMPARE_FIRED)?;
    m.add("COMPARE_MISSED", sdk::COMPARE_MISSED)?;
    m.add("COMPARE_LOW_WATER", sdk::COMPARE_LOW_WATER)?;
    m.add("COMPARE_TABLE_LEN", sdk::COMPARE_TABLE_LEN)?;
    m.add_class::<card::Card>()?;
    m.add_class::<card::CardInfo>()?;
    m.add_class::<card::CardListing>()?;
    m.add_class::<card::Sim>()?;
    m.add_class::<card::FireRecord>()?;
    m.add_class::<card::Event>()?;
    m.add_class::<card::Events>()?;
    m.add_class::<card::SafetyStatus>()?;
    m.add_class::<safety::SafetySettings>()?;
    m.add_class::<safety::CardSafetySettings>()?;
    m.add_class::<safety::StopInfo>()?;
    m.add_class::<motion::Axis>()?;
    m.add_class::<motion::MoveLimits>()?;
    m.add_class::<motion::Motion>()?;
    m.add_class::<motion::Status>()?;
    m.add_class::<group::Group>()?;
    m.add_class::<group::GroupMotion>()?;
    m.add_class::<group::GroupHoming>()?;
    m.add_class::<group::GroupStatus>()?;
    m.add_class::<group::PathLimits>()?;
    m.add_class::<group::Segment>()?;
    m.add_class::<group::Nurbs>()?;
    m.add_class::<path::PathOutput>()?;
    m.add_class::<io::Compare>()?;
    m.add_class::<io::Probe>()?;
    m.add_class::<io::AnalogInput>()?;
    m.add_class::<timed::TimedScope>()?;
    m.add_class::<cardset::CardSet>()?;
    m.add_class::<cardset::SyncScope>()?;
    m.add_class::<cardset::PathSettings>()?;
    m.add_class::<cardset::SetPath>()?;
    m.add_class::<cardset::SetPathProgress>()?;
    m.add_class::<machine::Compensation>()?;
    m.add_class::<machine::PsoStatus>()?;
    m.add_class::<machine::Gantry>()?;
    m.add_class::<machine::GantryHoming>()?;
    m.add_class::<machine::GantrySide>()?;
    m.add_class::<machine::GantryStatus>()?;
    m.add_class::<servo::ServoFilter>()?;
    m.add_class::<servo::FreqResponse>()?;
    m.add_function(wrap_pyfunction!(servo::pidff_for_drive, m)?)?;
    m.add_function(wrap_pyfunction!(servo::die_bonder_pdplus, m)?)?;
    m.add_class::<scope::Scope>()?;
    m.add_class::<scope::Capture>()?;
    m.add_class::<trace::ReplayReport>()?;
    m.add_function(wrap_pyfunction!(trace::replay, m)?)?;
    m.add("TRACE_ENV", sdk::TRACE_ENV)?;
    Ok(())
}
