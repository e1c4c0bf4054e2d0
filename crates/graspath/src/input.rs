//! Opening input files ([`open`]) and reading them whole with a cap on their size ([`read`]).
//!
//! Only regular files are read: a FIFO, a socket, a device or a folder is refused before any
//! byte is read ([`open`] opens without blocking, so a FIFO without a writer cannot hang the
//! program), and a file that is far too large (a multi-gigabyte file named by mistake) is a
//! clear error before it is read, never an exhausted machine.
//!
//! Each kind of input has its cap here, well above any real file of that kind. Readers that
//! stream their file (candidate files, see [`crate::grasp`]) check sizes on their own.
//!
//! [`plain_serde_message`] puts the messages of the serde-based readers in the file's words.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// The largest robot description read (URDF, MJCF, SRDF; bytes): 256 MiB. Published
/// descriptions are below 1 MiB; their meshes are separate files.
pub const MAX_ROBOT_FILE_BYTES: u64 = 256 << 20;
/// The largest task file read (bytes): 256 MiB. Candidates in bulk belong in a candidate file,
/// which is streamed.
pub const MAX_TASK_FILE_BYTES: u64 = 256 << 20;
/// The largest grasp model file read (bytes): 1 GiB.
pub const MAX_MODEL_FILE_BYTES: u64 = 1 << 30;
/// The largest point cloud or mesh file read (bytes): 4 GiB, room for
/// [`MAX_CLOUD_POINTS`](crate::cloud::MAX_CLOUD_POINTS) points written as text with normals.
pub const MAX_CLOUD_FILE_BYTES: u64 = 4 << 30;

/// The whole content of the file at `path`, refused above `max_bytes` bytes: before anything
/// is read when the file's length is known, otherwise once `max_bytes + 1` bytes have been
/// read. The refusal is an error of kind [`io::ErrorKind::FileTooLarge`] that gives the cap.
pub fn read(path: &Path, max_bytes: u64) -> io::Result<Vec<u8>> {
    let file = open(path)?;
    let known = file
        .metadata()
        .ok()
        .filter(std::fs::Metadata::is_file)
        .map(|m| m.len());
    if known.is_some_and(|len| len > max_bytes) {
        return Err(too_large(max_bytes));
    }
    let mut bytes = Vec::with_capacity(known.unwrap_or(0).try_into().unwrap_or(0));
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large(max_bytes));
    }
    Ok(bytes)
}

/// Opens the regular file at `path` for reading. A FIFO, socket, device or folder is refused
/// with an error of kind [`io::ErrorKind::InvalidInput`] that says what it is; on Unix the file
/// is opened without blocking (`O_NONBLOCK`, which changes nothing for a regular file), so a
/// FIFO is refused at once instead of waiting for a writer.
pub fn open(path: &Path) -> io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let file_type = file.metadata()?.file_type();
    if file_type.is_file() {
        return Ok(file);
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("{}, not a regular file", kind_of(&file_type)),
    ))
}

#[cfg(unix)]
fn kind_of(file_type: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_dir() {
        "a folder"
    } else if file_type.is_fifo() {
        "a FIFO (named pipe)"
    } else if file_type.is_socket() {
        "a socket"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn kind_of(file_type: &std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        "a folder"
    } else {
        "a special file"
    }
}

/// [`read`] as UTF-8 text; text that is not UTF-8 is an error of kind
/// [`io::ErrorKind::InvalidData`].
pub fn read_to_string(path: &Path, max_bytes: u64) -> io::Result<String> {
    String::from_utf8(read(path, max_bytes)?).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "the file is not UTF-8 text (byte {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

fn too_large(max_bytes: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::FileTooLarge,
        format!(
            "the file is larger than {max_bytes} bytes ({} MiB), the most accepted for it",
            max_bytes >> 20
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn a_file_up_to_the_cap_is_read_whole_and_a_larger_one_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.txt");
        std::fs::write(&path, "0123456789").unwrap();
        assert_eq!(read(&path, 10).unwrap(), b"0123456789");
        assert_eq!(read_to_string(&path, 64).unwrap(), "0123456789");
        let err = read(&path, 9).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::FileTooLarge);
        assert!(err.to_string().contains("larger than 9 bytes"), "{err}");
    }

    #[test]
    fn a_huge_sparse_file_is_refused_without_being_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.ply");
        let file = File::create(&path).unwrap();
        // Sparse: no disk blocks, and reading it would take 4 GiB of memory.
        file.set_len(MAX_CLOUD_FILE_BYTES + 1).unwrap();
        let err = read(&path, MAX_CLOUD_FILE_BYTES).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::FileTooLarge);
        assert!(err.to_string().contains("4096 MiB"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn special_files_are_refused_before_anything_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        // No writer: a blocking open would wait for ever.
        for (path, what) in [
            (fifo.as_path(), "a FIFO (named pipe)"),
            (Path::new("/dev/zero"), "a character device"),
            (dir.path(), "a folder"),
        ] {
            let err = read(path, 1 << 16).unwrap_err();
            assert_eq!(err.kind(), io::ErrorKind::InvalidInput, "{path:?}");
            assert_eq!(err.to_string(), format!("{what}, not a regular file"));
        }
    }

    #[test]
    fn text_that_is_not_utf8_is_refused_with_its_position() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.urdf");
        let mut file = File::create(&path).unwrap();
        file.write_all(b"<robot>\xff</robot>").unwrap();
        let err = read_to_string(&path, 1 << 10).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidData);
        assert!(err.to_string().contains("byte 7"), "{err}");
        assert!(read(Path::new("/no/such/file"), 10).is_err());
    }
}

/// A message of serde's about a file's value in the words of the file's reader rather than
/// Rust's: `expected usize` reads `expected a whole number ≥ 0`, `expected f64` reads
/// `expected a number`, `expected struct TaskObject` reads `expected a mapping of fields`
/// (the types serde names are the program's, not the file format's).
pub fn plain_serde_message(message: &str) -> String {
    const WORDS: [(&str, &str); 12] = [
        ("usize", "a whole number ≥ 0"),
        ("u64", "a whole number ≥ 0"),
        ("u32", "a whole number from 0 to 4294967295"),
        ("u16", "a whole number from 0 to 65535"),
        ("u8", "a whole number from 0 to 255"),
        ("isize", "a whole number"),
        ("i64", "a whole number"),
        ("i32", "a whole number from -2147483648 to 2147483647"),
        ("f64", "a number"),
        ("f32", "a number"),
        ("bool", "true or false"),
        ("char", "a single character"),
    ];
    let mut out = String::with_capacity(message.len() + 16);
    let mut rest = message;
    while let Some(at) = rest.find("expected ") {
        let (before, after) = rest.split_at(at + "expected ".len());
        out.push_str(before);
        let word_end = after
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(after.len());
        let word = &after[..word_end];
        if let Some((_, plain)) = WORDS.iter().find(|(rust, _)| *rust == word) {
            out.push_str(plain);
            rest = &after[word_end..];
        } else if word == "struct" {
            // `struct Name`: the name is the program's.
            let name = after[word_end..].trim_start_matches(' ');
            let name_end = name
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(name.len());
            out.push_str("a mapping of fields");
            rest = &name[name_end..];
        } else {
            rest = after;
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod plain_message_tests {
    use super::plain_serde_message;

    #[test]
    fn rust_type_names_become_the_file_format_words() {
        assert_eq!(
            plain_serde_message("invalid value: integer `-5`, expected usize"),
            "invalid value: integer `-5`, expected a whole number ≥ 0"
        );
        assert_eq!(
            plain_serde_message("invalid type: boolean `true`, expected f64"),
            "invalid type: boolean `true`, expected a number"
        );
        assert_eq!(
            plain_serde_message("invalid type: integer `5`, expected struct TaskObject"),
            "invalid type: integer `5`, expected a mapping of fields"
        );
        // Other words, and words that only start like a type, are kept.
        for kept in [
            "invalid length 2, expected an array of length 3",
            "unknown field `robt`, expected one of `robot`, `arms`",
            "expected u8s",
            "expected",
        ] {
            assert_eq!(plain_serde_message(kept), kept);
        }
    }
}
