//! Files the simulator reads (scenarios, sweep shards): read whole only below a size cap, checked
//! while reading, so that `/dev/zero`, a pipe or a huge file is refused instead of filling memory.

use std::io::Read;
use std::path::Path;

use hya_core::Short;

/// The text of the file at `path`, if it is UTF-8 of at most `limit` bytes; otherwise why not,
/// naming the limit.
pub fn read_text(path: &Path, limit: u64) -> Result<String, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    let mut bytes = Vec::new();
    // Metadata can lie (`/dev/zero`, pipes report 0): the cap holds on what is read.
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(format!("larger than the {} MiB this file may have", Short(limit as f64 / (1u64 << 20) as f64)));
    }
    String::from_utf8(bytes).map_err(|e| format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()))
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
        assert!(read_text(Path::new("/dev/zero"), 1 << 20).unwrap_err().contains("larger than"));
    }
}
