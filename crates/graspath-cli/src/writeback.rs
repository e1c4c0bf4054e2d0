//! A large output file handed to the disk as it is written. The output folder is flushed to
//! disk before it is moved into place (`FolderWriter::finish`); a multi-gigabyte candidates
//! file would otherwise be written to disk only then, on one thread, after the last candidate.
//! On Linux the written bytes are handed to the disk every [`STRIDE`] bytes
//! (`sync_file_range(SYNC_FILE_RANGE_WRITE)`, which starts the writing and returns at once), so
//! the final flush has little left to wait for; elsewhere the file is written as is.

use std::fs::File;
use std::io::{self, Write};

/// How many bytes are written between two hand-offs to the disk.
const STRIDE: u64 = 32 << 20;

/// A file whose bytes are handed to the disk as they are written (see the module).
pub(crate) struct Writeback {
    file: File,
    /// Bytes written so far, and where the bytes not yet handed to the disk start.
    written: u64,
    handed: u64,
}

impl Writeback {
    pub(crate) fn new(file: File) -> Self {
        Self {
            file,
            written: 0,
            handed: 0,
        }
    }

    /// Starts writing `[handed, written)` to the disk, without waiting for it.
    #[cfg(target_os = "linux")]
    fn hand_to_disk(&mut self) {
        use std::os::fd::AsRawFd;
        let (Ok(offset), Ok(length)) = (
            libc::off64_t::try_from(self.handed),
            libc::off64_t::try_from(self.written - self.handed),
        ) else {
            return;
        };
        // SAFETY: the descriptor is this open file's; the call reads no memory of ours. A
        // failure only means the final flush does the writing, so it is ignored.
        unsafe {
            libc::sync_file_range(
                self.file.as_raw_fd(),
                offset,
                length,
                libc::SYNC_FILE_RANGE_WRITE,
            );
        }
        self.handed = self.written;
    }

    #[cfg(not(target_os = "linux"))]
    fn hand_to_disk(&mut self) {
        self.handed = self.written;
    }
}

impl Write for Writeback {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        let n = self.file.write(bytes)?;
        self.written += n as u64;
        if self.written - self.handed >= STRIDE {
            self.hand_to_disk();
        }
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    #[test]
    fn the_bytes_written_are_the_file_and_are_handed_to_the_disk_every_stride() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big");
        let mut file = Writeback::new(File::create(&path).unwrap());
        let piece: Vec<u8> = (0..1 << 20).map(|i: u32| (i % 251) as u8).collect();
        let pieces = (STRIDE >> 20) as usize + 5;
        for _ in 0..pieces {
            file.write_all(&piece).unwrap();
        }
        file.flush().unwrap();
        assert_eq!(file.written, (pieces << 20) as u64);
        assert_eq!(
            file.handed, STRIDE,
            "handed to the disk once, after the first stride"
        );
        drop(file);
        let mut back = Vec::new();
        File::open(&path).unwrap().read_to_end(&mut back).unwrap();
        assert_eq!(back.len(), pieces << 20);
        assert!(back.chunks(1 << 20).all(|chunk| chunk == piece.as_slice()));
    }
}
