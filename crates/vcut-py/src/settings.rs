//! Frame settings from Python keywords: each keyword a field of `vcut_shade::FrameSettings`,
//! read through the same serde definitions as `--json` and `Frame.settings` write, so a name or
//! a value is refused naming the keyword.

use crate::VcutsError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use serde_json::Value;
use vcut_shade::FrameSettings;

/// `base` with each keyword of `keywords` set; an unknown keyword or a value of the wrong kind
/// or range raises `VcutsError` naming it.
pub(crate) fn with(base: &FrameSettings, keywords: Option<&Bound<'_, PyDict>>) -> PyResult<FrameSettings> {
    let mut fields = match serde_json::to_value(base) {
        Ok(Value::Object(m)) => m,
        _ => unreachable!("settings serialise to an object"),
    };
    let mut settings = base.clone();
    for (k, v) in keywords.into_iter().flat_map(|d| d.iter()) {
        let key: String = k.extract()?;
        let value = json(&v).map_err(|e| VcutsError::new_err(format!("{key}: {e}")))?;
        let value = match (fields.get(&key), value) {
            // A dict of caches changes only the caches it names.
            (Some(Value::Object(old)), Value::Object(new)) => {
                let mut merged = old.clone();
                merged.extend(new);
                Value::Object(merged)
            }
            (_, value) => value,
        };
        fields.insert(key.clone(), value);
        settings = serde_json::from_value(Value::Object(fields.clone())).map_err(|e| {
            VcutsError::new_err(format!("{key} = {}: {e}", v.repr().map_or("?".into(), |r| r.to_string())))
        })?;
    }
    settings.validate().map_err(|e| VcutsError::new_err(e.to_string()))?;
    Ok(settings)
}

/// A Python value as JSON: None, bool, int, float (finite), str, and lists and dicts of them.
fn json(v: &Bound<'_, PyAny>) -> Result<Value, String> {
    if v.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = v.extract::<bool>() {
        return Ok(Value::Bool(b));
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(Value::from(i));
    }
    if let Ok(x) = v.extract::<f64>() {
        return serde_json::Number::from_f64(x).map(Value::Number).ok_or_else(|| format!("{x} is not finite"));
    }
    if let Ok(s) = v.extract::<String>() {
        return Ok(Value::String(s));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut m = serde_json::Map::new();
        for (k, x) in d.iter() {
            m.insert(k.extract::<String>().map_err(|e| e.to_string())?, json(&x)?);
        }
        return Ok(Value::Object(m));
    }
    if v.cast::<PyList>().is_ok() || v.cast::<PyTuple>().is_ok() {
        let items: Vec<Bound<'_, PyAny>> =
            v.try_iter().map_err(|e| e.to_string())?.collect::<Result<_, _>>().map_err(|e| e.to_string())?;
        return items.iter().map(json).collect::<Result<Vec<_>, _>>().map(Value::Array);
    }
    Err(format!("{} is not a setting's value", v.repr().map_or("?".into(), |r| r.to_string())))
}
