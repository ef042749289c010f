//! Writes NumPy `.npy` files (format 1.0, little-endian float32, C order), the dump format of
//! `relief trace`.

use std::io::Write;
use std::path::Path;

/// Writes `values` with `shape` to `path` as a float32 `.npy` array.
pub fn write_npy_f32(path: &Path, shape: &[usize], values: &[f32]) -> std::io::Result<()> {
    let expected: usize = shape.iter().product();
    if expected != values.len() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} values for shape {shape:?}", values.len()),
        ));
    }
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let tuple = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {tuple}, }}");
    // Magic (6) + version (2) + header length (2) + header + '\n' must be a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    out.write_all(b"\x93NUMPY\x01\x00")?;
    out.write_all(&(header.len() as u16).to_le_bytes())?;
    out.write_all(header.as_bytes())?;
    for v in values {
        out.write_all(&v.to_le_bytes())?;
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    #[test]
    fn header_is_aligned_and_data_follows() {
        let path = std::env::temp_dir().join(format!("relief-npy-{}.npy", std::process::id()));
        super::write_npy_f32(&path, &[2, 3, 8], &[1.5f32; 48]).expect("writes");
        let bytes = std::fs::read(&path).expect("reads");
        let _ = std::fs::remove_file(&path);
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + header_len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + header_len]).expect("ascii");
        assert!(header.contains("'shape': (2, 3, 8)") && header.ends_with('\n'));
        assert_eq!(bytes.len(), 10 + header_len + 48 * 4);
        assert_eq!(
            &bytes[10 + header_len..14 + header_len],
            &1.5f32.to_le_bytes()
        );
        assert!(
            super::write_npy_f32(&path, &[2], &[1.0]).is_err(),
            "shape mismatch is refused"
        );
    }
}
