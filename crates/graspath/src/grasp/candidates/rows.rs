//! Reading a graspath candidate file record by record, from its start or from a remembered
//! position, in bounded memory: one CSV record or one JSON entry at a time. The whole-file
//! reader ([`read_candidates`](super::read_candidates)) and the chunked one
//! ([`CandidateFile`](super::CandidateFile)) both read through [`scan_file`] and
//! [`scan_from`], so a file gives the same candidates and the same errors either way.

use super::{too_large, Candidate, CandidateError, Entry, Raw, MAX_FILE_BYTES};
use serde::de::{self, DeserializeSeed, Deserializer as _, MapAccess, SeqAccess, Visitor};
use std::cell::{Cell, RefCell};
use std::fmt;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

/// The layout of a graspath candidate file, from its extension: `.csv` is CSV, anything else
/// JSON.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// A header line, then one candidate per record.
    Csv,
    /// `{"format": …, "candidates": [...]}` or a bare list of candidates.
    Json,
}

impl Layout {
    fn of(path: &Path) -> Self {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
        {
            Self::Csv
        } else {
            Self::Json
        }
    }
}

/// Where a candidate is in its file, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Location {
    /// A JSON candidate by its position in the list: `candidates[3]`.
    Entry(usize),
    /// A CSV record by the line it starts on (1-based, the header is line 1): `line 7`.
    Line(u64),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Entry(i) => write!(f, "candidates[{i}]"),
            Self::Line(l) => write!(f, "line {l}"),
        }
    }
}

/// Where reading can start again at a candidate.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Resume {
    /// CSV: the record's position (byte offset, line and record number).
    Csv(csv::Position),
    /// JSON: the byte offset just after the previous entry's closing `}` (or after the list's
    /// `[` for the first entry); `first` says no `,` precedes the entry.
    Json { offset: u64, first: bool },
}

/// One candidate read from the file: its position in candidate order, where it is, where
/// reading can start again at it, and the candidate.
pub(super) struct Row {
    pub index: usize,
    pub location: Location,
    pub resume: Resume,
    pub candidate: Candidate,
}

/// Whether a scan goes on after a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Flow {
    Continue,
    Stop,
}

/// Why a scan ended early: the file is wrong, or the row consumer failed.
pub(super) enum ScanError<E> {
    File(CandidateError),
    Sink(E),
}

impl ScanError<std::convert::Infallible> {
    /// The file's error (a consumer that cannot fail leaves no other).
    pub(super) fn into_file(self) -> CandidateError {
        match self {
            Self::File(e) => e,
            Self::Sink(never) => match never {},
        }
    }
}

/// `(location, message)` of a fault in the file, before the file's name is attached.
type Fault = (String, String);

fn fault_of<E>(file: &Path, (location, message): Fault) -> ScanError<E> {
    ScanError::File(CandidateError::new(
        file.display().to_string(),
        location,
        message,
    ))
}

/// The file opened for reading, refused above [`MAX_FILE_BYTES`] when its length is known.
fn open(path: &Path) -> Result<File, CandidateError> {
    let file = crate::input::open(path).map_err(|e| CandidateError::unreadable(path, e))?;
    if let Ok(metadata) = file.metadata() {
        if metadata.is_file() && metadata.len() > MAX_FILE_BYTES {
            return Err(CandidateError::unreadable(path, too_large(metadata.len())));
        }
    }
    Ok(file)
}

/// A reader that counts the bytes it hands on (the JSON entries' offsets) and refuses more
/// than [`MAX_FILE_BYTES`] (should the file grow while it is read).
struct Counted<'a, R> {
    inner: R,
    count: &'a Cell<u64>,
}

impl<R: Read> Read for Counted<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let count = self.count.get() + n as u64;
        self.count.set(count);
        if count > MAX_FILE_BYTES {
            return Err(too_large(count));
        }
        Ok(n)
    }
}

/// Reads the file from its start and hands every candidate, in file order, to `sink` until it
/// answers [`Flow::Stop`]. Each record is checked as it is read; the first fault ends the scan
/// with an error naming the file, the record (`candidates[3]`, `line 7`) and the field.
pub(super) fn scan_file<E>(
    path: &Path,
    sink: &mut dyn FnMut(Row) -> Result<Flow, E>,
) -> Result<(), ScanError<E>> {
    let file = open(path).map_err(ScanError::File)?;
    let count = Cell::new(0);
    let result = match Layout::of(path) {
        Layout::Csv => {
            let mut reader = csv_reader(Counted {
                inner: file,
                count: &count,
            });
            csv_columns(&mut reader)
                .map_err(|f| fault_of(path, f))
                .and_then(|columns| scan_csv(path, &mut reader, &columns, 0, sink))
        }
        Layout::Json => {
            // Byte by byte from the buffer, so the count is where the parser is.
            let reader = Counted {
                inner: BufReader::new(file),
                count: &count,
            };
            let mut de = serde_json::Deserializer::from_reader(reader);
            let state = JsonState::new(path, &count, sink, 0);
            let result = (&mut de)
                .deserialize_any(Document(&state))
                .and_then(|()| de.end());
            state.finish(result, |e| {
                fault_of(
                    path,
                    ("file".into(), format!("not a candidate document: {e}")),
                )
            })
        }
    };
    match result {
        Err(ScanError::File(_)) if count.get() > MAX_FILE_BYTES => Err(ScanError::File(
            CandidateError::unreadable(path, too_large(count.get())),
        )),
        other => other,
    }
}

/// Reads the file from a candidate's [`Resume`] position (the `index`-th candidate) and hands
/// the candidates from there to `sink`, as [`scan_file`] does. The file was checked whole
/// before: a record that no longer reads is reported as the file having changed.
pub(super) fn scan_from<E>(
    path: &Path,
    resume: &Resume,
    index: usize,
    sink: &mut dyn FnMut(Row) -> Result<Flow, E>,
) -> Result<(), ScanError<E>> {
    let mut file = open(path).map_err(ScanError::File)?;
    let cannot_read = |e: std::io::Error| ScanError::File(CandidateError::unreadable(path, e));
    match resume {
        Resume::Csv(position) => {
            let mut reader = csv_reader(file);
            let columns = csv_columns(&mut reader).map_err(|f| fault_of(path, f))?;
            reader
                .seek(position.clone())
                .map_err(|e| cannot_read(e.into()))?;
            scan_csv(path, &mut reader, &columns, index, sink)
        }
        Resume::Json { offset, first } => {
            file.seek(SeekFrom::Start(*offset)).map_err(cannot_read)?;
            let mut reader = BufReader::new(file);
            // Past the whitespace and the `,` between the previous entry and this one; the
            // rest of the list is then read as a list of its own.
            let mut offset = *offset;
            let mut comma = *first;
            loop {
                let buffer = reader.fill_buf().map_err(cannot_read)?;
                match buffer.first() {
                    Some(b' ' | b'\t' | b'\n' | b'\r') => {}
                    Some(b',') if !comma => comma = true,
                    Some(_) if comma => break,
                    _ => return Err(changed(path)),
                }
                reader.consume(1);
                offset += 1;
            }
            // The count starts one byte early for the `[` put in front.
            let count = Cell::new(offset - 1);
            let reader = Counted {
                inner: (&b"["[..]).chain(reader),
                count: &count,
            };
            let mut de = serde_json::Deserializer::from_reader(reader);
            let state = JsonState::new(path, &count, sink, index);
            let result = (&mut de).deserialize_seq(Entries(&state));
            state.finish(result, |_| changed(path))
        }
    }
}

/// The error of a file that no longer holds what it held when it was checked.
pub(super) fn changed<E>(path: &Path) -> ScanError<E> {
    fault_of(
        path,
        (
            "file".into(),
            "changed after it was checked; run again on the file as it is now".into(),
        ),
    )
}

// ---------------------------------------------------------------------------------------------
// CSV

/// The columns graspath reads; any other is refused.
const KNOWN: [&str; 15] = [
    "id",
    "label",
    "x",
    "y",
    "z",
    "qx",
    "qy",
    "qz",
    "qw",
    "likelihood",
    "log_likelihood",
    "contact_x",
    "contact_y",
    "contact_z",
    "hand_joints",
];

/// Which field of a record holds each of [`KNOWN`]'s columns (by their position in it).
struct Columns([Option<usize>; KNOWN.len()]);

const ID: usize = 0;
const LABEL: usize = 1;
const X: usize = 2;
const QX: usize = 5;
const LIKELIHOOD: usize = 9;
const LOG_LIKELIHOOD: usize = 10;
const CONTACT_X: usize = 11;
const HAND_JOINTS: usize = 14;

fn csv_reader<R: Read>(reader: R) -> csv::Reader<R> {
    csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(reader)
}

/// Reads and checks the header line.
fn csv_columns<R: Read>(reader: &mut csv::Reader<R>) -> Result<Columns, Fault> {
    let headers = reader
        .headers()
        .map_err(|e| ("line 1".to_string(), e.to_string()))?;
    if let Some(unknown) = headers.iter().find(|h| !h.is_empty() && !KNOWN.contains(h)) {
        // A name is quoted only when it looks like one: the first line of a file that is no
        // candidate file at all (a link to a secret, say) is not echoed.
        let looks_like_a_name = unknown.len() <= 32
            && unknown
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == ' ');
        let message = if looks_like_a_name {
            format!("unknown column '{unknown}'")
        } else {
            format!(
                "an unknown column that is not a column name ({} characters); the columns are {}",
                unknown.chars().count(),
                KNOWN.join(", ")
            )
        };
        return Err(("line 1".into(), message));
    }
    let columns = Columns(KNOWN.map(|name| headers.iter().position(|h| h == name)));
    if let Some(k) = (X..QX + 4).find(|k| columns.0[*k].is_none()) {
        return Err(("line 1".into(), format!("missing column '{}'", KNOWN[k])));
    }
    Ok(columns)
}

/// Hands the records from the reader's position on to `sink`; the first is the `index`-th
/// candidate.
fn scan_csv<R: Read, E>(
    path: &Path,
    reader: &mut csv::Reader<R>,
    columns: &Columns,
    mut index: usize,
    sink: &mut dyn FnMut(Row) -> Result<Flow, E>,
) -> Result<(), ScanError<E>> {
    let mut record = csv::StringRecord::new();
    loop {
        let position = reader.position().clone();
        let more = reader.read_record(&mut record).map_err(|e| {
            let line = e.position().map_or(position.line(), csv::Position::line);
            fault_of(path, (format!("line {line}"), e.to_string()))
        })?;
        if !more {
            return Ok(());
        }
        let start = record.position().cloned().unwrap_or(position);
        let line = start.line();
        let candidate =
            csv_candidate(columns, &record, index, line).map_err(|f| fault_of(path, f))?;
        let row = Row {
            index,
            location: Location::Line(line),
            resume: Resume::Csv(start),
            candidate,
        };
        if sink(row).map_err(ScanError::Sink)? == Flow::Stop {
            return Ok(());
        }
        index += 1;
    }
}

/// The candidate of one CSV record starting on `line`; `index` is its id when the file gives
/// none.
fn csv_candidate(
    columns: &Columns,
    record: &csv::StringRecord,
    index: usize,
    line: u64,
) -> Result<Candidate, Fault> {
    let at = || format!("line {line}");
    let text = |k: usize| columns.0[k].and_then(|c| record.get(c));
    let number = |k: usize| -> Result<Option<f64>, Fault> {
        match text(k) {
            None | Some("") => Ok(None),
            Some(value) => value.parse::<f64>().map(Some).map_err(|_| {
                (
                    at(),
                    format!("column '{}': '{value}' is not a number", KNOWN[k]),
                )
            }),
        }
    };
    let need = |k: usize| -> Result<f64, Fault> {
        number(k)?.ok_or_else(|| (at(), format!("column '{}' is empty", KNOWN[k])))
    };
    let id = match text(ID) {
        None | Some("") => None,
        Some(value) => Some(value.parse::<usize>().map_err(|_| {
            (
                at(),
                format!("column 'id': '{value}' is not a whole number"),
            )
        })?),
    };
    let contact = match (
        number(CONTACT_X)?,
        number(CONTACT_X + 1)?,
        number(CONTACT_X + 2)?,
    ) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z]),
        (None, None, None) => None,
        _ => {
            return Err((
                at(),
                "contact_x, contact_y and contact_z go together".into(),
            ))
        }
    };
    let raw = Raw {
        id,
        label: text(LABEL).filter(|s| !s.is_empty()).map(str::to_string),
        pose: None,
        matrix: None,
        xyz: Some([need(X)?, need(X + 1)?, need(X + 2)?]),
        quaternion: Some([need(QX)?, need(QX + 1)?, need(QX + 2)?, need(QX + 3)?]),
        likelihood: number(LIKELIHOOD)?,
        log_likelihood: number(LOG_LIKELIHOOD)?,
        contact,
        hand_joints: match text(HAND_JOINTS) {
            None => Vec::new(),
            Some(values) => values
                .split(|c: char| c.is_whitespace() || c == ';')
                .filter(|v| !v.is_empty())
                .map(|v| {
                    v.parse::<f64>()
                        .map_err(|_| (at(), format!("column 'hand_joints': '{v}' is not a number")))
                })
                .collect::<Result<Vec<f64>, _>>()?,
        },
    };
    raw.into_candidate(index)
        .map_err(|(field, message)| (at(), format!("{field}: {message}")))
}

// ---------------------------------------------------------------------------------------------
// JSON

/// What the JSON visitors share: the file, the byte count of the reader, the row consumer,
/// the next candidate's index, and why the scan stopped (a fault of the file with its
/// location, the consumer's error, or the consumer's [`Flow::Stop`]).
struct JsonState<'a, E> {
    path: &'a Path,
    offset: &'a Cell<u64>,
    sink: RefCell<&'a mut dyn FnMut(Row) -> Result<Flow, E>>,
    index: Cell<usize>,
    ended: RefCell<Option<Ended<E>>>,
}

/// Why the visitors stopped the deserializer.
enum Ended<E> {
    Fault(Fault),
    Sink(E),
    Stopped,
}

impl<'a, E> JsonState<'a, E> {
    fn new(
        path: &'a Path,
        offset: &'a Cell<u64>,
        sink: &'a mut dyn FnMut(Row) -> Result<Flow, E>,
        index: usize,
    ) -> Self {
        Self {
            path,
            offset,
            sink: RefCell::new(sink),
            index: Cell::new(index),
            ended: RefCell::new(None),
        }
    }

    /// Stops the deserializer for `why`.
    fn end<D: de::Error>(&self, why: Ended<E>) -> D {
        *self.ended.borrow_mut() = Some(why);
        D::custom("stopped")
    }

    /// The scan's outcome from the deserializer's: the reason the visitors recorded, else
    /// the deserializer's own error as `fault` makes it.
    fn finish(
        self,
        result: Result<(), serde_json::Error>,
        fault: impl FnOnce(serde_json::Error) -> ScanError<E>,
    ) -> Result<(), ScanError<E>> {
        match (self.ended.into_inner(), result) {
            (Some(Ended::Fault(f)), _) => Err(fault_of(self.path, f)),
            (Some(Ended::Sink(e)), _) => Err(ScanError::Sink(e)),
            (Some(Ended::Stopped), _) | (None, Ok(())) => Ok(()),
            (None, Err(e)) => Err(fault(e)),
        }
    }
}

/// The document: a bare list of candidates, or an object with `candidates` and optionally
/// `format`, `version` and `frame`, checked as they come.
struct Document<'s, 'a, E>(&'s JsonState<'a, E>);

impl<'de, E> Visitor<'de> for Document<'_, '_, E> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an object with 'candidates' or a list")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<(), A::Error> {
        Entries(self.0).visit_seq(seq)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        const FIELDS: &[&str] = &["format", "version", "frame", "candidates"];
        let mut seen = [false; 4];
        while let Some(key) = map.next_key::<String>()? {
            let k = FIELDS
                .iter()
                .position(|f| *f == key)
                .ok_or_else(|| de::Error::unknown_field(&key, FIELDS))?;
            if std::mem::replace(&mut seen[k], true) {
                return Err(de::Error::duplicate_field(FIELDS[k]));
            }
            let refused = match FIELDS[k] {
                "format" => map
                    .next_value::<Option<String>>()?
                    .filter(|f| f != "graspath-candidates")
                    .map(|f| format!("expected 'graspath-candidates', got '{f}'")),
                "version" => map
                    .next_value::<Option<u32>>()?
                    .filter(|v| *v != 1)
                    .map(|v| format!("version {v} is not supported (this reads version 1)")),
                "frame" => map
                    .next_value::<Option<String>>()?
                    .filter(|f| f != "object")
                    .map(|f| format!("poses must be in the object frame, got '{f}'")),
                _ => {
                    map.next_value_seed(List(self.0))?;
                    None
                }
            };
            if let Some(message) = refused {
                return Err(self.0.end(Ended::Fault((FIELDS[k].to_string(), message))));
            }
        }
        if !seen[3] {
            return Err(de::Error::missing_field("candidates"));
        }
        Ok(())
    }
}

/// The `candidates` list of a wrapped document.
struct List<'s, 'a, E>(&'s JsonState<'a, E>);

impl<'de, E> DeserializeSeed<'de> for List<'_, '_, E> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_seq(Entries(self.0))
    }
}

/// The entries of a list, each read whole as a JSON value (one candidate at a time), then
/// checked as a candidate.
struct Entries<'s, 'a, E>(&'s JsonState<'a, E>);

impl<'de, E> Visitor<'de> for Entries<'_, '_, E> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a list of candidates")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let state = self.0;
        let mut first = true;
        loop {
            // An entry is an object: the reader stops right after its `}`, so the count is
            // where the next entry (after its `,`) begins.
            let resume = Resume::Json {
                offset: state.offset.get(),
                first,
            };
            let Some(value) = seq.next_element::<serde_json::Value>()? else {
                return Ok(());
            };
            first = false;
            let index = state.index.get();
            let location = Location::Entry(index);
            let candidate = json_candidate(value, location, index)
                .map_err(|fault| state.end(Ended::Fault(fault)))?;
            let row = Row {
                index,
                location,
                resume,
                candidate,
            };
            let flow = (state.sink.borrow_mut())(row);
            match flow {
                Ok(Flow::Continue) => state.index.set(index + 1),
                Ok(Flow::Stop) => return Err(state.end(Ended::Stopped)),
                Err(e) => return Err(state.end(Ended::Sink(e))),
            }
        }
    }
}

/// One JSON entry at `location` as a candidate; `index` is its id when the entry gives none.
fn json_candidate(
    value: serde_json::Value,
    location: Location,
    index: usize,
) -> Result<Candidate, Fault> {
    let entry: Entry = serde_json::from_value(value).map_err(|e| {
        (
            location.to_string(),
            crate::input::plain_serde_message(&e.to_string()),
        )
    })?;
    Raw {
        id: entry.id,
        label: entry.label,
        pose: entry.pose,
        matrix: entry.object_from_wrist,
        xyz: entry.xyz,
        quaternion: entry.quaternion,
        likelihood: entry.likelihood,
        log_likelihood: entry.log_likelihood,
        contact: entry.contact,
        hand_joints: entry.hand_joints,
    }
    .into_candidate(index)
    .map_err(|(field, message)| (format!("{location}.{field}"), message))
}
