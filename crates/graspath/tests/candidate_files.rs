//! Candidate files read in chunks ([`CandidateFile`]) against the whole-file reader
//! ([`read_candidates`]): the same candidates in the same order at every chunk size, each
//! candidate found again by its position, the same largest log-likelihood, the same error for a
//! bad record anywhere in the file, and an error when the file changes after it was indexed.
//! The files are generated here, with the values written checked against what is read.

use graspath::grasp::{read_candidates, Candidate, CandidateError, CandidateFile, INDEX_STRIDE};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// More candidates than a few index strides and than the chunk sizes tried, not a multiple of
/// either.
const N: usize = 3 * INDEX_STRIDE + 13;

/// The values written for candidate `k`: id, wrist position (m), unit quaternion
/// `[x, y, z, w]`, likelihood.
struct Written {
    id: usize,
    xyz: [f64; 3],
    quaternion: [f64; 4],
    likelihood: f64,
}

fn written(k: usize) -> Written {
    let a = k as f64 * 0.37;
    let q = UnitQuaternion::from_quaternion(Quaternion::new(
        a.cos(),
        a.sin(),
        0.3 * (2.0 * a).cos(),
        0.2,
    ));
    Written {
        // Unique ids in shuffled order (7919 is prime, so k ↦ 7919 k mod N is one to one).
        id: (k * 7919) % N + 1000,
        xyz: [0.1 * a.sin(), 0.05 * a.cos(), 0.01 * (k % 7) as f64],
        quaternion: [q.i, q.j, q.k, q.w],
        likelihood: 0.05 + (k % 11) as f64 / 11.0,
    }
}

/// A CSV file of `n` candidates; labels hold commas, quotes and, every 10th, a line break, so
/// records and lines differ. `bad`: record `k`'s line replaced by `line`.
fn csv_text(n: usize, bad: Option<(usize, &str)>) -> String {
    let mut text = String::from(
        "id, label, x, y, z, qx, qy, qz, qw, likelihood, contact_x, contact_y, contact_z, hand_joints\n",
    );
    for k in 0..n {
        if let Some((_, line)) = bad.filter(|(at, _)| *at == k) {
            writeln!(text, "{line}").unwrap();
            continue;
        }
        let w = written(k);
        let label = if k % 10 == 3 {
            format!("\"grasp {k},\nsecond \"\"line\"\"\"")
        } else {
            format!("grasp {k}")
        };
        let contact = if k % 4 == 0 {
            format!("{},{},{}", w.xyz[0], w.xyz[1], w.xyz[2] + 0.01)
        } else {
            ",,".into()
        };
        writeln!(
            text,
            "{},{label},{},{},{},{},{},{},{},{},{contact},{}",
            w.id,
            w.xyz[0],
            w.xyz[1],
            w.xyz[2],
            w.quaternion[0],
            w.quaternion[1],
            w.quaternion[2],
            w.quaternion[3],
            w.likelihood,
            if k % 5 == 0 { "0.01 0.02" } else { "" },
        )
        .unwrap();
    }
    text
}

/// The line CSV record `k` starts on in [`csv_text`] (the header is line 1).
fn csv_line(k: usize) -> usize {
    2 + k + (0..k).filter(|j| j % 10 == 3).count()
}

/// A JSON entry for candidate `k` in one of the three pose forms, laid out differently.
fn json_entry(k: usize) -> String {
    let w = written(k);
    let [x, y, z] = w.xyz;
    let [qx, qy, qz, qw] = w.quaternion;
    match k % 3 {
        0 => format!(
            "{{\"id\": {}, \"label\": \"grasp {k}\",\n  \"pose\": {{\"xyz\": [{x}, {y}, {z}], \"quaternion\": [{qx}, {qy}, {qz}, {qw}]}},\n  \"likelihood\": {}}}",
            w.id, w.likelihood
        ),
        1 => format!(
            "{{\"id\":{},\"xyz\":[{x},{y},{z}],\"quaternion\":[{qx},{qy},{qz},{qw}],\"log_likelihood\":{},\"contact\":[{x},{y},{}],\"hand_joints\":[0.5]}}",
            w.id,
            w.likelihood.ln(),
            z + 0.01
        ),
        _ => {
            let r = UnitQuaternion::from_quaternion(Quaternion::new(qw, qx, qy, qz))
                .to_rotation_matrix();
            let t = Vector3::new(x, y, z);
            let rows: Vec<String> = (0..3)
                .map(|i| format!("[{}, {}, {}, {}]", r[(i, 0)], r[(i, 1)], r[(i, 2)], t[i]))
                .chain(std::iter::once("[0, 0, 0, 1]".to_string()))
                .collect();
            format!(
                "{{ \"likelihood\" : {} ,\t\"object_from_wrist\": [{}], \"id\": {} }}",
                w.likelihood,
                rows.join(", "),
                w.id
            )
        }
    }
}

/// A JSON file of `n` candidates, wrapped (`{"format", "version", "frame", "candidates"}`) or
/// a bare list. `bad`: entry `k` replaced by `entry`.
fn json_text(n: usize, wrapped: bool, bad: Option<(usize, &str)>) -> String {
    let entries: Vec<String> = (0..n)
        .map(|k| match bad {
            Some((at, entry)) if at == k => entry.to_string(),
            _ => json_entry(k),
        })
        .collect();
    let list = format!("[\n{}\n ]", entries.join(" ,\n"));
    if wrapped {
        format!(
            "{{\"format\": \"graspath-candidates\", \"version\": 1, \"frame\": \"object\",\n \"candidates\": {list}}}\n"
        )
    } else {
        list
    }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Every candidate of the file in chunks of `size`, each chunk checked to be 1 to `size` long.
fn in_chunks(file: &CandidateFile, size: usize) -> Vec<Candidate> {
    let mut read = Vec::new();
    file.for_each_chunk(size, |chunk| -> Result<(), CandidateError> {
        assert!(!chunk.is_empty() && chunk.len() <= size, "{}", chunk.len());
        read.extend(chunk);
        Ok(())
    })
    .unwrap();
    read
}

fn check_indexed_equals_whole(path: &Path) {
    let whole = read_candidates(path).unwrap();
    assert_eq!(whole.len(), N);
    // The reader itself against the values written.
    for (k, c) in whole.iter().enumerate() {
        let w = written(k);
        assert_eq!(c.id, w.id);
        assert_eq!(c.object_from_wrist.translation.vector, Vector3::from(w.xyz));
        assert!((c.log_likelihood - w.likelihood.ln()).abs() < 1e-12);
    }
    let file = CandidateFile::index(path).unwrap();
    assert_eq!(file.len(), N);
    let max = whole
        .iter()
        .map(|c| c.log_likelihood)
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(file.max_log_likelihood(), max);
    for size in [1, 7, 256, N + 3] {
        assert_eq!(in_chunks(&file, size), whole, "chunks of {size}");
    }
    for (k, c) in whole.iter().enumerate() {
        assert_eq!(
            file.candidate(k).unwrap().as_ref(),
            Some(c),
            "candidate {k}"
        );
    }
    assert_eq!(file.candidate(N).unwrap(), None);
    assert_eq!(file.all().unwrap(), whole);
}

#[test]
fn an_indexed_csv_file_reads_the_whole_file_readers_candidates() {
    let dir = tempfile::tempdir().unwrap();
    check_indexed_equals_whole(&write(dir.path(), "c.csv", &csv_text(N, None)));
    let crlf = csv_text(N, None).replace('\n', "\r\n");
    check_indexed_equals_whole(&write(dir.path(), "crlf.csv", &crlf));
}

#[test]
fn an_indexed_json_file_reads_the_whole_file_readers_candidates() {
    let dir = tempfile::tempdir().unwrap();
    check_indexed_equals_whole(&write(dir.path(), "w.json", &json_text(N, true, None)));
    check_indexed_equals_whole(&write(dir.path(), "b.json", &json_text(N, false, None)));
    let crlf = json_text(N, false, None).replace('\n', "\r\n");
    check_indexed_equals_whole(&write(dir.path(), "crlf.json", &crlf));
}

/// Indexing and reading whole fail alike, with the error `location` and a message containing
/// `message`.
fn check_same_error(path: &Path, location: &str, message: &str) -> CandidateError {
    let whole = read_candidates(path).unwrap_err();
    let indexed = CandidateFile::index(path).unwrap_err();
    assert_eq!(indexed, whole);
    assert_eq!(whole.location, location, "{whole}");
    assert!(whole.message.contains(message), "{whole}");
    assert!(whole
        .file
        .ends_with(path.file_name().unwrap().to_str().unwrap()));
    whole
}

#[test]
fn a_bad_record_in_the_middle_gives_the_whole_file_readers_error() {
    let dir = tempfile::tempdir().unwrap();
    let k = N / 2;
    let first = written(0);
    let csv_cases = [
        (
            "7,x,0,zero,0,0,0,0,1,1,,,,".to_string(),
            "column 'y': 'zero' is not a number",
        ),
        (
            "7,x,0,0,0,0,0,0,2,1,,,,".to_string(),
            "must be a unit quaternion",
        ),
        (
            "7,x,0,0,0,0,0,0,1,1,,,,0.1 oops".to_string(),
            "'oops' is not a number",
        ),
        (
            "7,x,0,0,0,0,0,0,1".to_string(),
            "found record with 9 fields",
        ),
        (
            format!("{},x,0,0,0,0,0,0,1,1,,,,", first.id),
            &format!("id {} is used twice (also by line 2)", first.id),
        ),
    ];
    for (i, (line, message)) in csv_cases.iter().enumerate() {
        let path = write(
            dir.path(),
            &format!("bad{i}.csv"),
            &csv_text(N, Some((k, line))),
        );
        check_same_error(&path, &format!("line {}", csv_line(k)), message);
    }
    let json_cases = [
        (
            r#"{"id": 7, "xyz": [0, 0, 0], "quaternion": [0, 0, 0, 1], "score": 1}"#.to_string(),
            format!("candidates[{k}]"),
            "unknown field `score`".to_string(),
        ),
        (
            r#"{"id": 7, "xyz": [0, 0, 50], "quaternion": [0, 0, 0, 1]}"#.to_string(),
            format!("candidates[{k}].xyz"),
            "are the units metres?".to_string(),
        ),
        (
            format!(
                r#"{{"id": {}, "xyz": [0, 0, 0], "quaternion": [0, 0, 0, 1]}}"#,
                first.id
            ),
            format!("candidates[{k}]"),
            format!("id {} is used twice (also by candidates[0])", first.id),
        ),
        (
            r#"{"id": 7, "xyz": [0, 0, 0], "quaternion": [0, 0, 0, 1]"#.to_string(),
            "file".to_string(),
            "not a candidate document".to_string(),
        ),
    ];
    for (i, (entry, location, message)) in json_cases.iter().enumerate() {
        for wrapped in [true, false] {
            let path = write(
                dir.path(),
                &format!("bad{i}_{wrapped}.json"),
                &json_text(N, wrapped, Some((k, entry))),
            );
            check_same_error(&path, location, message);
        }
    }
    // The document's own fields, wherever they are.
    let text = json_text(N, true, None).replace("\"frame\": \"object\",", "");
    let late = format!(
        "{}, \"frame\": \"camera\"}}\n",
        text.trim_end().trim_end_matches('}')
    );
    check_same_error(
        &write(dir.path(), "late.json", &late),
        "frame",
        "poses must be in the object frame, got 'camera'",
    );
}

#[test]
fn a_file_changed_after_it_was_indexed_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("c.csv", csv_text(N, None)),
        ("w.json", json_text(N, true, None)),
    ] {
        let path = write(dir.path(), name, &text);
        let file = CandidateFile::index(&path).unwrap();
        std::fs::write(&path, &text[..text.len() / 2]).unwrap();
        let chunks = file
            .for_each_chunk(16, |_| -> Result<(), CandidateError> { Ok(()) })
            .unwrap_err();
        let one = file.candidate(N - 1).unwrap_err();
        for err in [chunks, one] {
            assert_eq!(err.location, "file", "{err}");
            assert!(
                err.message.contains("changed after it was checked"),
                "{err}"
            );
        }
        std::fs::remove_file(&path).unwrap();
        let gone = file.candidate(0).unwrap_err();
        assert!(gone.message.contains("cannot read"), "{gone}");
    }
}

/// A rewrite in place with the same length and the modification time set back (the case that
/// mixed two files into one ranking) is an error too.
#[test]
fn a_file_rewritten_with_its_length_and_time_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("c.csv", csv_text(N, None)),
        ("w.json", json_text(N, true, None)),
    ] {
        let path = write(dir.path(), name, &text);
        let modified = std::fs::metadata(&path).unwrap().modified().unwrap();
        let file = CandidateFile::index(&path).unwrap();
        // The same bytes but one digit of the last candidate's position.
        let at = text
            .rfind(|c: char| c.is_ascii_digit() && c != '0')
            .unwrap();
        let mut other = text.clone().into_bytes();
        other[at] = if other[at] == b'1' { b'2' } else { b'1' };
        assert_eq!(other.len(), text.len());
        std::fs::write(&path, &other).unwrap();
        std::fs::File::options()
            .write(true)
            .open(&path)
            .unwrap()
            .set_modified(modified)
            .unwrap();
        assert_eq!(
            std::fs::metadata(&path).unwrap().modified().unwrap(),
            modified
        );
        let chunks = file
            .for_each_chunk(16, |_| -> Result<(), CandidateError> { Ok(()) })
            .unwrap_err();
        let one = file.candidate(N - 1).unwrap_err();
        for err in [chunks, one] {
            assert!(
                err.message.contains("changed after it was checked"),
                "{name}: {err}"
            );
        }
    }
}

#[test]
fn only_a_regular_file_is_indexed() {
    let dir = tempfile::tempdir().unwrap();
    assert!(!CandidateFile::can_index(dir.path()));
    let err = CandidateFile::index(dir.path()).unwrap_err();
    // The reading refuses it; the operating-system-level reason is the error's source.
    let chain = graspath::Chain(&err).to_string();
    assert!(chain.contains("a folder, not a regular file"), "{chain}");
    assert_eq!(
        graspath::fault_of(&err).unwrap().kind,
        graspath::ErrorKind::File
    );
}
