//! Files hya reads whole (URDFs, scenarios, friction files, sweep shards): only regular files,
//! and only up to a size cap checked while reading.
//!
//! A named pipe (FIFO) blocks `open` until a writer comes, possibly forever, and a device or a
//! pipe claims a size of 0 whatever it yields: both are refused by the file's type before it is
//! opened, and the type is checked again on the open file. (A path swapped for a FIFO between
//! the check and the open would still block the open; opening with `O_NONBLOCK` would close that
//! race, at the cost of a platform constant, and the race needs someone who already controls the
//! path.)

use std::fs::FileType;
use std::io::Read;
use std::path::Path;

/// Why a file was not read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// The operating system refused (no such file, no permission, …).
    #[error("cannot read: {0}")]
    Io(String),
    /// Not a regular file: a folder, a named pipe, a device or a socket.
    #[error(
        "is {0}, not a regular file: hya reads only regular files (a pipe or a device could block it or never end)"
    )]
    NotRegular(&'static str),
    /// More bytes than the cap.
    #[error("larger than the {limit} bytes this file may have")]
    TooLarge {
        /// The size the file claims, where that is over the cap; `None` when reading stopped
        /// at the cap.
        size: Option<u64>,
        /// The cap, bytes.
        limit: u64,
    },
    /// Not UTF-8 text.
    #[error("not UTF-8 text (byte {0})")]
    NotUtf8(usize),
}

/// What a file type that is not a regular file is, for the message.
fn kind(file_type: FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a folder"
    } else {
        "not a file"
    }
}

/// Refuses a file type that is not a regular file.
fn regular(file_type: FileType) -> Result<(), ReadError> {
    if file_type.is_file() {
        Ok(())
    } else {
        Err(ReadError::NotRegular(kind(file_type)))
    }
}

/// The bytes of the regular file at `path` (links followed), at most `limit` of them.
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let io = |e: std::io::Error| ReadError::Io(e.to_string());
    regular(std::fs::metadata(path).map_err(io)?.file_type())?;
    let file = std::fs::File::open(path).map_err(io)?;
    let metadata = file.metadata().map_err(io)?;
    regular(metadata.file_type())?;
    if metadata.len() > limit {
        return Err(ReadError::TooLarge { size: Some(metadata.len()), limit });
    }
    let mut bytes = Vec::new();
    // A file may grow after its size was read: the cap holds on what is read.
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { size: None, limit });
    }
    Ok(bytes)
}

/// The text of the regular file at `path`, if it is UTF-8 of at most `limit` bytes.
pub fn read_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    String::from_utf8(read_bytes(path, limit)?).map_err(|e| ReadError::NotUtf8(e.utf8_error().valid_up_to()))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn only_regular_files_within_the_cap_are_read() {
        let dir = std::env::temp_dir().join(format!("hya-urdf-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.txt");
        std::fs::write(&path, "x".repeat(100)).unwrap();
        assert_eq!(read_text(&path, 100).unwrap().len(), 100);
        assert_eq!(read_text(&path, 99), Err(ReadError::TooLarge { size: Some(100), limit: 99 }));
        std::fs::write(&path, [b'a', 0xff]).unwrap();
        assert_eq!(read_text(&path, 99), Err(ReadError::NotUtf8(1)));
        assert_eq!(read_text(&dir, 99), Err(ReadError::NotRegular("a folder")));
        assert!(matches!(read_text(&dir.join("none"), 99), Err(ReadError::Io(_))));
        #[cfg(unix)]
        {
            assert_eq!(read_text(Path::new("/dev/zero"), 99), Err(ReadError::NotRegular("a device")));
            // A FIFO with no writer: refused at once, where opening it would block for ever.
            let fifo = dir.join("fifo");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
            assert!(made.success());
            assert_eq!(read_text(&fifo, 99), Err(ReadError::NotRegular("a named pipe (FIFO)")));
            let message = read_text(&fifo, 99).unwrap_err().to_string();
            assert!(message.contains("named pipe") && message.contains("not a regular file"), "{message}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
