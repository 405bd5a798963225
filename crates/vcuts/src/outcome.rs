//! The one printer of command outcomes. Each command returns a typed outcome that derives
//! `Serialize`, its fields named as the keys scripts read; [`print`] writes it on stdout as
//! `key=value` lines in field order (or, with `--json`, as one JSON object), and Python's dicts
//! come from the same serialisation. An outcome serialises flat (nested parts with
//! `#[serde(flatten)]`); `None` fields print nothing.
//!
//! In `key=value` lines a number with a fraction prints with at most six significant digits (as
//! figures were always printed: rounded for reading); JSON keeps every digit.

use serde::Serialize;
use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether outcomes print as JSON (`--json`).
static JSON: AtomicBool = AtomicBool::new(false);

/// Prints outcomes as one JSON object each (`true`, `--json`) or as `key=value` lines.
pub fn set_json(json: bool) {
    JSON.store(json, Ordering::Relaxed);
}

/// Writes `outcome` on stdout: `key=value` lines, or one JSON object with `--json`.
pub fn print<T: Serialize>(outcome: &T) {
    match render(outcome, JSON.load(Ordering::Relaxed)) {
        Ok(text) => print!("{text}"),
        Err(e) => log::error!("the outcome does not serialise: {e}"),
    }
}

/// The text [`print`] writes for `outcome`.
pub fn render<T: Serialize>(outcome: &T, json: bool) -> Result<String, serde_json::Error> {
    if json {
        return Ok(serde_json::to_string(outcome)? + "\n");
    }
    Ok(lines(outcome)?.into_iter().map(|(k, v)| format!("{k}={v}\n")).collect())
}

/// `outcome` as `(key, value)` pairs in field order, values as `key=value` lines write them
/// (`None` fields left out). A list of records (an object table) is one line per record under
/// the same key, each `field:value` separated by spaces.
pub fn lines<T: Serialize>(outcome: &T) -> Result<Vec<(String, String)>, serde_json::Error> {
    // serde_json writes fields in declaration order; reading the text back into `Ordered`
    // keeps that order (a `serde_json::Value` map would sort the keys).
    let text = serde_json::to_string(outcome)?;
    let Ordered::Map(fields) = serde_json::from_str::<Ordered>(&text)? else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (k, v) in fields {
        match v {
            Ordered::List(items) if items.iter().any(|i| matches!(i, Ordered::Map(_))) => {
                out.extend(items.iter().filter_map(|i| i.text().map(|t| (k.clone(), t))));
            }
            v => out.extend(v.text().map(|t| (k, t))),
        }
    }
    Ok(out)
}

/// A JSON value with its object's keys in the order they were written.
#[derive(Debug, Clone, PartialEq)]
enum Ordered {
    Null,
    Bool(bool),
    Number(serde_json::Number),
    String(String),
    List(Vec<Ordered>),
    Map(Vec<(String, Ordered)>),
}

impl Ordered {
    /// The value as a `key=value` line writes it; `None` for null.
    fn text(&self) -> Option<String> {
        Some(match self {
            Ordered::Null => return None,
            Ordered::Bool(b) => b.to_string(),
            Ordered::Number(n) => match n.as_f64() {
                Some(x) if n.is_f64() => significant(x),
                _ => n.to_string(),
            },
            Ordered::String(s) => s.clone(),
            Ordered::List(items) => items.iter().filter_map(Ordered::text).collect::<Vec<_>>().join(","),
            Ordered::Map(fields) => {
                fields.iter().filter_map(|(k, v)| v.text().map(|t| format!("{k}:{t}"))).collect::<Vec<_>>().join(" ")
            }
        })
    }
}

/// `x` with at most six significant digits (trailing zeros dropped).
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = 6 - 1 - x.abs().log10().floor() as i32;
    if digits <= 0 {
        return format!("{:.0}", x);
    }
    let s = format!("{:.*}", digits as usize, x);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

impl<'de> Deserialize<'de> for Ordered {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Ordered, D::Error> {
        d.deserialize_any(OrderedVisitor)
    }
}

struct OrderedVisitor;

impl<'de> Visitor<'de> for OrderedVisitor {
    type Value = Ordered;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_unit<E>(self) -> Result<Ordered, E> {
        Ok(Ordered::Null)
    }

    fn visit_none<E>(self) -> Result<Ordered, E> {
        Ok(Ordered::Null)
    }

    fn visit_bool<E>(self, v: bool) -> Result<Ordered, E> {
        Ok(Ordered::Bool(v))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Ordered, E> {
        Ok(Ordered::Number(v.into()))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Ordered, E> {
        Ok(Ordered::Number(v.into()))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Ordered, E> {
        Ok(serde_json::Number::from_f64(v).map_or(Ordered::Null, Ordered::Number))
    }

    fn visit_str<E>(self, v: &str) -> Result<Ordered, E> {
        Ok(Ordered::String(v.into()))
    }

    fn visit_string<E>(self, v: String) -> Result<Ordered, E> {
        Ok(Ordered::String(v))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Ordered, A::Error> {
        let mut items = Vec::new();
        while let Some(x) = seq.next_element()? {
            items.push(x);
        }
        Ok(Ordered::List(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Ordered, A::Error> {
        let mut fields = Vec::new();
        while let Some((k, v)) = map.next_entry::<String, Ordered>()? {
            fields.push((k, v));
        }
        Ok(Ordered::Map(fields))
    }
}

/// Milliseconds since `start`.
pub fn ms_since(start: std::time::Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Inner {
        b_ms: f64,
        c: Option<u32>,
    }

    #[derive(Serialize)]
    struct Row {
        name: &'static str,
        at: [f32; 3],
    }

    #[derive(Serialize)]
    struct Outer {
        z: String,
        #[serde(flatten)]
        inner: Inner,
        a: Vec<&'static str>,
        skipped: Option<f64>,
        n: u64,
        yes: bool,
        row: Vec<Row>,
    }

    #[test]
    fn lines_keep_field_order_round_figures_and_leave_out_none() {
        let o = Outer {
            z: "x y".into(),
            inner: Inner { b_ms: 12.3456789, c: Some(3) },
            a: vec!["p", "q"],
            skipped: None,
            n: 12_345_678_901,
            yes: true,
            row: vec![Row { name: "a", at: [1.0, 0.5, 0.0] }, Row { name: "b", at: [0.0; 3] }],
        };
        assert_eq!(
            render(&o, false).unwrap(),
            "z=x y\nb_ms=12.3457\nc=3\na=p,q\nn=12345678901\nyes=true\nrow=name:a at:1,0.5,0\nrow=name:b at:0,0,0\n"
        );
        let json: serde_json::Value = serde_json::from_str(&render(&o, true).unwrap()).unwrap();
        assert_eq!(json["b_ms"], 12.3456789);
        assert_eq!(json["skipped"], serde_json::Value::Null);
    }

    #[test]
    fn significant_digits() {
        for (x, s) in
            [(0.000123456789, "0.000123457"), (1234567.8, "1234568"), (0.5, "0.5"), (2.0, "2"), (-3.25, "-3.25")]
        {
            assert_eq!(significant(x), s);
        }
    }
}
