//! The candidate record's columns as numpy arrays (`Selection.arrays()`, `select_batch`) and
//! the schema itself (`graspath.record_columns()`), all read off
//! [`graspath::select::record::COLUMNS`].

use crate::convert::{array, error};
use graspath::select::record::{
    column_named, outputs, Cell, Column, JsonPlace, Kind, Row, COLUMNS,
};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// Sets the record columns of `output` ([`outputs::ARRAYS`] or [`outputs::BATCH`]) over `rows`
/// in `dict`: a float as float64 and a nullable count as float64 (NaN where absent; an infinite
/// `mu_linf` stays infinite), a required count as int64, a flag as bool (false where absent), a
/// required text as a str array and a nullable one as an object array (`None` where absent), a
/// point as `(k, 3)`, a pose as `(k, 4, 4)` and a per-sample series as `(k, samples)` (NaN
/// where absent, or the values of the column's numpy fallback).
pub fn set_numpy_columns<'py>(
    py: Python<'py>,
    dict: &Bound<'py, PyDict>,
    rows: &[Row<'_>],
    output: u8,
    samples: usize,
) -> PyResult<()> {
    for column in COLUMNS.iter().filter(|c| c.in_output(output)) {
        dict.set_item(column.name, numpy_column(py, column, rows, samples)?)?;
    }
    Ok(())
}

fn numpy_column<'py>(
    py: Python<'py>,
    column: &Column,
    rows: &[Row<'_>],
    samples: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let k = rows.len();
    let cells = || rows.iter().map(|r| (column.value)(r));
    let nan = f64::NAN;
    Ok(match column.kind {
        Kind::Float => PyArray1::from_vec(
            py,
            cells()
                .map(|c| match c {
                    Cell::Float(v) => v.unwrap_or(nan),
                    _ => nan,
                })
                .collect(),
        )
        .into_any(),
        Kind::Count => {
            let counts = cells().map(|c| match c {
                Cell::Count(v) => v,
                _ => None,
            });
            if column.nullable {
                PyArray1::from_vec(py, counts.map(|v| v.map_or(nan, |v| v as f64)).collect())
                    .into_any()
            } else {
                PyArray1::from_vec(py, counts.map(|v| v.unwrap_or(0) as i64).collect()).into_any()
            }
        }
        Kind::Flag => PyArray1::from_vec(
            py,
            cells()
                .map(|c| matches!(c, Cell::Flag(Some(true))))
                .collect(),
        )
        .into_any(),
        Kind::Text => {
            let texts: Vec<Option<&str>> = cells()
                .map(|c| match c {
                    Cell::Text(v) => v,
                    _ => None,
                })
                .collect();
            text_array(py, texts, column.nullable)?
        }
        Kind::Point => {
            let flat: Vec<f64> = cells()
                .flat_map(|c| match c {
                    Cell::Point(Some(p)) => p,
                    _ => [nan; 3],
                })
                .collect();
            array(py, flat, &[k, 3])?.into_any()
        }
        Kind::Pose => {
            let flat: Vec<f64> = cells()
                .flat_map(|c| match c {
                    Cell::Pose(m) => *m.as_flattened().first_chunk::<16>().expect("4 × 4"),
                    _ => [nan; 16],
                })
                .collect();
            array(py, flat, &[k, 4, 4])?.into_any()
        }
        Kind::Series => {
            let fallback = column.numpy_fallback.and_then(column_named);
            let mut flat = vec![nan; k * samples];
            for (row, (r, cell)) in rows.iter().zip(cells()).enumerate() {
                let cell = match (cell, fallback) {
                    (Cell::Samples(None), Some(other)) => (other.value)(r),
                    (cell, _) => cell,
                };
                let out = &mut flat[row * samples..(row + 1) * samples];
                match cell {
                    Cell::Samples(Some(values)) => {
                        for (o, v) in out.iter_mut().zip(values) {
                            *o = v.unwrap_or(nan);
                        }
                    }
                    Cell::Floats(values) => {
                        for (o, v) in out.iter_mut().zip(values) {
                            *o = *v;
                        }
                    }
                    _ => {}
                }
            }
            array(py, flat, &[k, samples])?.into_any()
        }
        Kind::Bodies | Kind::Motion => {
            return Err(error(format!(
                "the record column {} ({}) has no numpy form",
                column.name,
                column.kind.name()
            )))
        }
    })
}

/// Texts as a numpy array: `str` when none is absent (`nullable` false), else `object` with
/// `None` where absent.
fn text_array<'py>(
    py: Python<'py>,
    texts: Vec<Option<&str>>,
    nullable: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = py.import("numpy")?;
    let builtins = py.import("builtins")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item(
        "dtype",
        builtins.getattr(if nullable { "object" } else { "str" })?,
    )?;
    numpy.call_method("array", (PyList::new(py, texts)?,), Some(&kwargs))
}

/// The names of the outputs a column is part of.
fn output_names(column: &Column) -> Vec<&'static str> {
    [
        (outputs::JSON, "json"),
        (outputs::JSON_LINES, "jsonl"),
        (outputs::PARQUET, "parquet"),
        (outputs::ARRAYS, "arrays"),
        (outputs::BATCH, "select_batch"),
    ]
    .into_iter()
    .filter(|(bit, _)| column.in_output(*bit))
    .map(|(_, name)| name)
    .collect()
}

/// The candidate record's columns, in order, as dicts: ``name``, ``type`` (``float64``,
/// ``uint64``, ``bool``, ``string``, …), ``nullable``, ``unit``, ``doc`` and ``outputs`` (the
/// outputs that carry it: ``json``, ``jsonl``, ``parquet``, ``arrays``, ``select_batch``) and
/// ``json_field`` (its place in a JSON record: the name, or ``group.name`` inside a group such
/// as ``failure``; ``None`` when no JSON output carries it). Every per-candidate output is
/// read off this list; see ``docs/candidate-record.md``.
#[pyfunction]
pub fn record_columns(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for column in COLUMNS {
        let dict = PyDict::new(py);
        dict.set_item("name", column.name)?;
        dict.set_item("type", column.kind.name())?;
        dict.set_item("nullable", column.nullable)?;
        dict.set_item("unit", column.unit)?;
        dict.set_item("doc", column.doc)?;
        dict.set_item("outputs", output_names(column))?;
        dict.set_item("json_field", json_field(column))?;
        list.append(dict)?;
    }
    Ok(list)
}

/// A column's place in a JSON record (`failure.reason` inside a group), `None` when neither
/// JSON output carries it.
fn json_field(column: &Column) -> Option<String> {
    if !(column.in_output(outputs::JSON) || column.in_output(outputs::JSON_LINES)) {
        return None;
    }
    Some(match column.json {
        JsonPlace::Top => column.name.to_string(),
        JsonPlace::In(group, name) => format!("{}.{name}", group.name()),
    })
}
