//! Files the simulator reads (scenarios, sweep shards): read whole only below a size cap, checked
//! while reading, and regular files only, so that `/dev/zero`, a FIFO or a huge file is refused
//! instead of filling memory or blocking.

use std::path::Path;

use hya_core::Short;
use hya_urdf::file::ReadError;

/// The text of the regular file at `path`, if it is UTF-8 of at most `limit` bytes; otherwise why
/// not, naming the limit in MiB (see [`hya_urdf::file::read_text`]).
pub fn read_text(path: &Path, limit: u64) -> Result<String, String> {
    hya_urdf::file::read_text(path, limit).map_err(|e| match e {
        ReadError::TooLarge { .. } => {
            format!("larger than the {} MiB this file may have", Short(limit as f64 / (1u64 << 20) as f64))
        }
        other => other.to_string(),
    })
}

/// The SHA-256 of the regular file at `path` (at most [`hya_urdf::MAX_FILE_BYTES`]), lower-case
/// hex, for a report to name exactly which file it ran on; why not, if it cannot be read now.
pub fn sha256_of(path: &Path) -> Result<String, String> {
    let bytes = hya_urdf::file::read_bytes(path, hya_urdf::MAX_FILE_BYTES as u64).map_err(|e| e.to_string())?;
    Ok(crate::io::output::sha256_hex(&bytes))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn files_beyond_the_cap_are_refused_while_reading() {
        let path = std::env::temp_dir().join(format!("hya-input-{}", std::process::id()));
        std::fs::write(&path, "x".repeat(100)).unwrap();
        assert_eq!(read_text(&path, 100).unwrap().len(), 100);
        assert!(read_text(&path, 99).unwrap_err().contains("larger than"));
        std::fs::write(&path, [0xff, 0xfe]).unwrap();
        assert!(read_text(&path, 99).unwrap_err().contains("not UTF-8"));
        std::fs::remove_file(&path).unwrap();
        #[cfg(unix)]
        assert!(read_text(Path::new("/dev/zero"), 1 << 20).unwrap_err().contains("a device, not a regular file"));
    }
}
