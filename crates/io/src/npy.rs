//! Minimal `.npy` writer (NumPy format 1.0) for integer and float grids, so Python users load
//! basins and maps with `numpy.load`. Own code: the format is a fixed header plus raw
//! little-endian data, and a crate would add a dependency for twenty lines.

use crate::output::OutputError;
use std::path::Path;

fn write(path: &Path, descr: &str, shape: &[usize], data: &[u8]) -> Result<(), OutputError> {
    let shape_txt = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape_txt}, }}");
    // magic (6) + version (2) + header length (2) + header + newline, padded to 64 bytes
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let mut bytes = Vec::with_capacity(10 + header.len() + data.len());
    bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(data);
    crate::safe_write::write_bytes(path, &bytes)
}

/// Writes an `int64` array of the given shape (row-major).
pub fn write_i64(path: &Path, shape: &[usize], data: &[i64]) -> Result<(), OutputError> {
    let raw: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    write(path, "<i8", shape, &raw)
}

/// Writes a `float64` array of the given shape (row-major).
pub fn write_f64(path: &Path, shape: &[usize], data: &[f64]) -> Result<(), OutputError> {
    let raw: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    write(path, "<f8", shape, &raw)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_aligned_and_data_follows() {
        let p = std::env::temp_dir().join(format!("geardyn-npy-{}.npy", std::process::id()));
        write_i64(&p, &[2, 3], &[1, 2, 3, 4, 5, -1]).unwrap();
        let b = std::fs::read(&p).unwrap();
        assert_eq!(&b[..6], b"\x93NUMPY");
        let hl = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hl) % 64, 0);
        let header = std::str::from_utf8(&b[10..10 + hl]).unwrap();
        assert!(header.contains("'shape': (2, 3)") && header.ends_with('\n'));
        assert_eq!(b.len(), 10 + hl + 48);
        assert_eq!(i64::from_le_bytes(b[b.len() - 8..].try_into().unwrap()), -1);
        std::fs::remove_file(p).ok();
    }
}
