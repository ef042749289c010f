//! Small PNG files written by hand, so the fuzz seeds cover what the `image` crate's encoder
//! never writes: palette images and Adam7-interlaced ones. The image data is one stored
//! (uncompressed) deflate block, so a byte edit of a pixel stays a pixel edit.

/// The colour types used: grey, RGB, palette, RGBA.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colour {
    Grey = 0,
    Rgb = 2,
    Palette = 3,
    Rgba = 6,
}

impl Colour {
    fn samples(self) -> usize {
        match self {
            Colour::Grey | Colour::Palette => 1,
            Colour::Rgb => 3,
            Colour::Rgba => 4,
        }
    }
}

/// How one seed PNG is made.
#[derive(Debug, Clone, Copy)]
pub struct PngSpec {
    pub width: u32,
    pub height: u32,
    pub colour: Colour,
    /// 8 or 16 (palette: 8).
    pub depth: u8,
    pub interlaced: bool,
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

fn adler32(bytes: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for &x in bytes {
        a = (a + u32::from(x)) % 65521;
        b = (b + a) % 65521;
    }
    (b << 16) | a
}

/// A chunk: length, type, data, CRC over type and data.
pub fn chunk(kind: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = (data.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let mut covered = kind.to_vec();
    covered.extend_from_slice(data);
    out.extend_from_slice(&crc32(&covered).to_be_bytes());
    out
}

/// A zlib stream of stored deflate blocks (at most 65535 bytes each).
fn zlib_stored(raw: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = if raw.is_empty() {
        vec![&[]]
    } else {
        raw.chunks(65535).collect()
    };
    for (k, block) in blocks.iter().enumerate() {
        out.push(u8::from(k + 1 == blocks.len()));
        let len = block.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(block);
    }
    out.extend_from_slice(&adler32(raw).to_be_bytes());
    out
}

/// Adam7's passes: (first x, first y, step x, step y).
const ADAM7: [(u32, u32, u32, u32); 7] = [
    (0, 0, 8, 8),
    (4, 0, 8, 8),
    (0, 4, 4, 8),
    (2, 0, 4, 4),
    (0, 2, 2, 4),
    (1, 0, 2, 2),
    (0, 1, 1, 2),
];

/// The file's header chunk for `spec` (also what a structure-aware edit rewrites).
pub fn ihdr(spec: &PngSpec) -> Vec<u8> {
    let mut data = spec.width.to_be_bytes().to_vec();
    data.extend_from_slice(&spec.height.to_be_bytes());
    data.extend_from_slice(&[
        spec.depth,
        spec.colour as u8,
        0,
        0,
        u8::from(spec.interlaced),
    ]);
    chunk(b"IHDR", &data)
}

/// The PNG of `spec`, each sample a pattern of its position.
pub fn png(spec: &PngSpec) -> Vec<u8> {
    let bytes_per_sample = usize::from(spec.depth / 8);
    let pixel = spec.colour.samples() * bytes_per_sample;
    let sample = |x: u32, y: u32, s: usize| -> u8 {
        let v = x.wrapping_mul(37) ^ y.wrapping_mul(11) ^ (s as u32).wrapping_mul(5);
        if spec.colour == Colour::Palette {
            (v % 4) as u8
        } else {
            v as u8
        }
    };
    let passes: Vec<(u32, u32, u32, u32)> = if spec.interlaced {
        ADAM7.to_vec()
    } else {
        vec![(0, 0, 1, 1)]
    };
    let mut raw = Vec::new();
    for (x0, y0, dx, dy) in passes {
        let xs: Vec<u32> = (x0..spec.width).step_by(dx as usize).collect();
        if xs.is_empty() {
            continue;
        }
        for y in (y0..spec.height).step_by(dy as usize) {
            raw.push(0); // filter: none
            for &x in &xs {
                for s in 0..pixel {
                    raw.push(sample(x, y, s));
                }
            }
        }
    }
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend(ihdr(spec));
    if spec.colour == Colour::Palette {
        out.extend(chunk(
            b"PLTE",
            &[0, 0, 0, 80, 80, 80, 160, 160, 160, 255, 255, 255],
        ));
    }
    out.extend(chunk(b"IDAT", &zlib_stored(&raw)));
    out.extend(chunk(b"IEND", &[]));
    out
}

/// The seeds: 8- and 16-bit grey, 16-bit RGB, 8-bit RGBA, palette, and interlaced forms.
pub fn seeds() -> Vec<PngSpec> {
    let spec = |colour, depth, interlaced| PngSpec {
        width: 13,
        height: 9,
        colour,
        depth,
        interlaced,
    };
    vec![
        spec(Colour::Grey, 8, false),
        spec(Colour::Grey, 16, false),
        spec(Colour::Rgb, 16, false),
        spec(Colour::Rgba, 8, false),
        spec(Colour::Palette, 8, false),
        spec(Colour::Grey, 8, true),
        spec(Colour::Grey, 16, true),
        spec(Colour::Palette, 8, true),
    ]
}
