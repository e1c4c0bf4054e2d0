//! Reading an input file whole, with a cap on its size: a file that is far too large (a
//! multi-gigabyte file named by mistake, a device such as `/dev/zero`, a FIFO that never ends)
//! is a clear error after at most the cap has been read, never an exhausted machine.
//!
//! Each kind of input has its cap here, well above any real file of that kind. Readers that
//! stream their file (candidate files, see [`crate::grasp`]) check sizes on their own.

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
    let file = File::open(path)?;
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
    fn an_endless_stream_stops_at_the_cap() {
        // A device without a length: only the cap and one byte more are read.
        let err = read(Path::new("/dev/zero"), 1 << 16).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::FileTooLarge);
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
