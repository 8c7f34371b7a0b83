//! `motioncard.Error` and one subclass per [`ErrorKind`], made from `ErrorKind::ALL` when the
//! module loads (none can be missed): `BadAxisError`, `TimeoutError`, ... Each class has the
//! attributes `kind` (the kind's name, `"BadAxis"`), `code` (the C ABI's `MC_ERR_*` value)
//! and `description`.
use motioncard_sdk::ErrorKind;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;
use pyo3::types::PyType;
use std::ffi::CString;

pyo3::create_exception!(
    motioncard,
    MotioncardError,
    PyException,
    "An error of the motion card or the SDK; `kind` names its ErrorKind, each kind has its own subclass."
);

/// The subclasses, in `ErrorKind::ALL`'s order.
static CLASSES: GILOnceCell<Vec<Py<PyType>>> = GILOnceCell::new();

/// The Python class name of a kind.
pub(crate) fn class_name(kind: ErrorKind) -> String {
    format!("{kind:?}Error")
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    let base = py.get_type::<MotioncardError>();
    base.setattr("kind", py.None())?;
    base.setattr("code", py.None())?;
    base.setattr("description", py.None())?;
    m.add("Error", &base)?;
    let mut classes = Vec::new();
    let mut kinds = Vec::new();
    for &kind in ErrorKind::ALL {
        let name = class_name(kind);
        let qual = CString::new(format!("motioncard.{name}")).expect("no NUL");
        let doc = CString::new(kind.doc().replace('\0', "")).expect("no NUL");
        let ty = PyErr::new_type(py, &qual, Some(&doc), Some(&base), None)?;
        let t = ty.bind(py);
        t.setattr("kind", format!("{kind:?}"))?;
        t.setattr("code", kind.code())?;
        t.setattr("description", kind.description())?;
        m.add(name.as_str(), ty.bind(py))?;
        kinds.push((format!("{kind:?}"), name, kind.code(), kind.description()));
        classes.push(ty);
    }
    m.add("ERROR_KINDS", kinds)?;
    let _ = CLASSES.set(py, classes);
    Ok(())
}

/// An SDK error on its way to Python.
pub(crate) struct Error(pub motioncard_sdk::Error);

impl From<motioncard_sdk::Error> for Error {
    fn from(e: motioncard_sdk::Error) -> Self {
        Error(e)
    }
}

impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        of_kind(e.0.kind(), e.0.to_string())
    }
}

/// `r` with its error made a Python one.
pub(crate) fn py<T>(r: motioncard_sdk::Result<T>) -> PyResult<T> {
    r.map_err(|e| Error(e).into())
}

/// An error of `kind` raised by the binding itself (an argument Python cannot pass to the
/// SDK's typed call, such as a stop category that is not one).
pub(crate) fn of_kind(kind: ErrorKind, msg: String) -> PyErr {
    Python::with_gil(|py| {
        let i = ErrorKind::ALL.iter().position(|&k| k == kind);
        match (CLASSES.get(py), i) {
            (Some(c), Some(i)) => PyErr::from_type(c[i].bind(py).clone(), (msg,)),
            _ => MotioncardError::new_err(msg),
        }
    })
}

/// Raise the error of kind `kind` (its name, as `ErrorKind`'s) as every SDK error is raised:
/// through [`of_kind`], which picks its class. For the tests (`test_errors.py`: every kind
/// raises its own class); an unknown name is a `ValueError`.
#[pyfunction]
pub(crate) fn _raise_kind(kind: &str) -> PyResult<()> {
    let k = ErrorKind::ALL
        .iter()
        .copied()
        .find(|k| format!("{k:?}") == kind)
        .ok_or_else(|| pyo3::exceptions::PyValueError::new_err(format!("no kind {kind}")))?;
    Err(of_kind(k, format!("{kind}: {}", k.description())))
}
