//! A result [`Table`](crate::schema::Table) as a Parquet file (one row group, uncompressed,
//! plain columns: numbers `DOUBLE`, counts `INT64` (optional where a count may be absent), flags
//! `BOOLEAN`, names UTF-8 `BYTE_ARRAY`), written by `geardyn merge` beside the CSV files.
//!
//! Behind the `parquet` feature (off by default): the `parquet` crate (59.x, the last release
//! that builds with the workspace's Rust 1.87; 60 needs 1.88), without its arrow and compression
//! features, added 3 min 37 s to a release build of the CLI on the 2-core CI kind of machine
//! (measured 2026-11-26) — a quarter of the CI's time budget. Build with
//! `cargo build --release -p geardyn-cli --features parquet`, or read the CSV files with pandas
//! and pyarrow (`geardyn.distributed.merge` writes the Parquet table that way).

use crate::output::OutputError;
use crate::schema::{Table, Values};
use parquet::basic::{LogicalType, Repetition, Type as Physical};
use parquet::column::writer::ColumnWriter;
use parquet::data_type::ByteArray;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::path::Path;
use std::sync::Arc;

fn err(path: &Path, e: impl std::fmt::Display) -> OutputError {
    OutputError::Io {
        path: path.display().to_string(),
        source: std::io::Error::other(e.to_string()),
    }
}

/// Writes `table` as a Parquet file at `path` (whole, by an atomic rename).
pub fn write_table(path: &Path, table: &Table) -> Result<(), OutputError> {
    let fields = table
        .columns
        .iter()
        .map(|c| {
            let (t, rep, logical) = match c.values {
                Values::F64(_) => (Physical::DOUBLE, Repetition::REQUIRED, None),
                Values::I64(_) => (Physical::INT64, Repetition::REQUIRED, None),
                Values::OptI64(_) => (Physical::INT64, Repetition::OPTIONAL, None),
                Values::Bool(_) => (Physical::BOOLEAN, Repetition::REQUIRED, None),
                Values::Str(_) => (
                    Physical::BYTE_ARRAY,
                    Repetition::REQUIRED,
                    Some(LogicalType::String),
                ),
            };
            Type::primitive_type_builder(&c.name, t)
                .with_repetition(rep)
                .with_logical_type(logical)
                .build()
                .map(Arc::new)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| err(path, e))?;
    let schema = Arc::new(
        Type::group_type_builder("runs")
            .with_fields(fields)
            .build()
            .map_err(|e| err(path, e))?,
    );
    let props = Arc::new(WriterProperties::builder().build());
    let mut buf: Vec<u8> = Vec::new();
    {
        let mut w = SerializedFileWriter::new(&mut buf, schema, props).map_err(|e| err(path, e))?;
        let mut rg = w.next_row_group().map_err(|e| err(path, e))?;
        let mut k = 0;
        while let Some(mut col) = rg.next_column().map_err(|e| err(path, e))? {
            let values = &table.columns[k].values;
            k += 1;
            let r = match (col.untyped(), values) {
                (ColumnWriter::DoubleColumnWriter(w), Values::F64(v)) => {
                    w.write_batch(v, None, None)
                }
                (ColumnWriter::Int64ColumnWriter(w), Values::I64(v)) => {
                    w.write_batch(v, None, None)
                }
                (ColumnWriter::Int64ColumnWriter(w), Values::OptI64(v)) => {
                    let present: Vec<i64> = v.iter().flatten().copied().collect();
                    let def: Vec<i16> = v.iter().map(|x| i16::from(x.is_some())).collect();
                    w.write_batch(&present, Some(&def), None)
                }
                (ColumnWriter::BoolColumnWriter(w), Values::Bool(v)) => {
                    w.write_batch(v, None, None)
                }
                (ColumnWriter::ByteArrayColumnWriter(w), Values::Str(v)) => {
                    let b: Vec<ByteArray> = v.iter().map(|s| ByteArray::from(s.as_str())).collect();
                    w.write_batch(&b, None, None)
                }
                _ => unreachable!("the schema follows the columns"),
            };
            r.map_err(|e| err(path, e))?;
            col.close().map_err(|e| err(path, e))?;
        }
        rg.close().map_err(|e| err(path, e))?;
        w.close().map_err(|e| err(path, e))?;
    }
    crate::safe_write::write_bytes(path, &buf)
}
