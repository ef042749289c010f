//! Structure-aware damage to valid inputs: byte edits for binary files (cut short, bits
//! flipped, a length or count word overwritten with an extreme value, bytes inserted or cut
//! out) and tree edits for JSON (a value swapped for one of the wrong type, an extreme number,
//! a deep nest, a key removed), with raw tokens JSON itself forbids (NaN, Infinity, 1e999).

use proptest::prelude::*;
use serde_json::Value;

/// Words a count or length field is most likely to be mishandled at.
const EXTREME_WORDS: [u32; 8] = [
    0,
    1,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0xffff,
    0x1_0000,
    31_623, // squared, about 10^9
];

/// One edit of a byte string. Positions are taken modulo the length, so every edit applies.
#[derive(Debug, Clone)]
pub enum ByteEdit {
    /// Keeps the first `at` bytes.
    Truncate(usize),
    /// XORs the byte at `at` with a non-zero mask.
    Flip(usize, u8),
    /// Writes a little-endian word at `at`.
    Word(usize, u32),
    /// Writes a big-endian word at `at` (PNG's lengths and sizes).
    WordBe(usize, u32),
    /// Inserts bytes at `at`.
    Insert(usize, Vec<u8>),
    /// Cuts `len` bytes out from `at`.
    Cut(usize, usize),
}

fn word() -> impl Strategy<Value = u32> {
    prop_oneof![
        3 => proptest::sample::select(EXTREME_WORDS.to_vec()),
        1 => any::<u32>(),
    ]
}

/// Any one [`ByteEdit`].
pub fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    prop_oneof![
        any::<usize>().prop_map(ByteEdit::Truncate),
        (any::<usize>(), 1..=255u8).prop_map(|(at, m)| ByteEdit::Flip(at, m)),
        (any::<usize>(), word()).prop_map(|(at, w)| ByteEdit::Word(at, w)),
        (any::<usize>(), word()).prop_map(|(at, w)| ByteEdit::WordBe(at, w)),
        (
            any::<usize>(),
            proptest::collection::vec(any::<u8>(), 1..16)
        )
            .prop_map(|(at, b)| ByteEdit::Insert(at, b)),
        (any::<usize>(), 1..64usize).prop_map(|(at, n)| ByteEdit::Cut(at, n)),
    ]
}

/// One to four byte edits.
pub fn byte_edits() -> impl Strategy<Value = Vec<ByteEdit>> {
    proptest::collection::vec(byte_edit(), 1..=4)
}

fn put(data: &mut [u8], at: usize, bytes: [u8; 4]) {
    if data.is_empty() {
        return;
    }
    let at = at % data.len();
    let end = (at + 4).min(data.len());
    data[at..end].copy_from_slice(&bytes[..end - at]);
}

/// `data` with `edits` applied in order.
pub fn apply_bytes(data: &[u8], edits: &[ByteEdit]) -> Vec<u8> {
    let mut out = data.to_vec();
    for edit in edits {
        let len = out.len();
        match edit {
            ByteEdit::Truncate(at) => out.truncate(at % (len + 1)),
            ByteEdit::Flip(at, mask) if len > 0 => out[at % len] ^= mask,
            ByteEdit::Flip(..) => {}
            ByteEdit::Word(at, w) => put(&mut out, *at, w.to_le_bytes()),
            ByteEdit::WordBe(at, w) => put(&mut out, *at, w.to_be_bytes()),
            ByteEdit::Insert(at, bytes) => {
                let at = at % (len + 1);
                out.splice(at..at, bytes.iter().copied());
            }
            ByteEdit::Cut(at, n) => {
                let at = at % (len + 1);
                out.drain(at..(at + n).min(len));
            }
        }
    }
    out
}

/// What a JSON node is replaced with.
#[derive(Debug, Clone)]
pub enum Hostile {
    /// A number: huge, negative, fractional, 2^32, u64::MAX.
    Number(f64),
    /// u64::MAX, which no f64 holds exactly.
    MaxU64,
    /// A raw token JSON forbids or no f64 holds: `NaN`, `Infinity`, `-Infinity`, `1e999`.
    Token(&'static str),
    /// A value of another type.
    Wrong(Value),
    /// The value wrapped in `depth` arrays.
    Nest(usize),
    /// A long array of copies of the value.
    Repeat(usize),
}

/// One edit of a JSON tree: `node` picks among its nodes (modulo their count, in pre-order).
#[derive(Debug, Clone)]
pub enum JsonEdit {
    /// Replaces the node.
    Replace { node: usize, with: Hostile },
    /// Removes the node from its object or array.
    Remove { node: usize },
}

fn hostile() -> impl Strategy<Value = Hostile> {
    let numbers = [
        -1.0,
        0.0,
        0.5,
        -0.0,
        4_294_967_296.0,
        4_294_967_295.0,
        1e308,
        -1e308,
        1e-310,
        1e9,
    ];
    prop_oneof![
        proptest::sample::select(numbers.to_vec()).prop_map(Hostile::Number),
        Just(Hostile::MaxU64),
        proptest::sample::select(vec!["NaN", "Infinity", "-Infinity", "1e999", "-1e999"])
            .prop_map(Hostile::Token),
        prop_oneof![
            Just(Value::Null),
            Just(Value::Bool(true)),
            Just(Value::String("x".into())),
            Just(Value::String(String::new())),
            Just(Value::Array(Vec::new())),
            Just(Value::Object(Default::default())),
        ]
        .prop_map(Hostile::Wrong),
        // serde_json refuses past 128 levels; both sides of that limit.
        prop_oneof![Just(20usize), Just(127), Just(129), Just(1000)].prop_map(Hostile::Nest),
        prop_oneof![Just(2usize), Just(1000)].prop_map(Hostile::Repeat),
    ]
}

/// Any one [`JsonEdit`].
pub fn json_edit() -> impl Strategy<Value = JsonEdit> {
    prop_oneof![
        4 => (any::<usize>(), hostile()).prop_map(|(node, with)| JsonEdit::Replace { node, with }),
        1 => any::<usize>().prop_map(|node| JsonEdit::Remove { node }),
    ]
}

/// One to three JSON edits.
pub fn json_edits() -> impl Strategy<Value = Vec<JsonEdit>> {
    proptest::collection::vec(json_edit(), 1..=3)
}

/// JSON pointers to every node of `v`, in pre-order (the root is "").
fn pointers(v: &Value, at: String, out: &mut Vec<String>) {
    out.push(at.clone());
    match v {
        Value::Array(items) => {
            for (k, item) in items.iter().enumerate() {
                pointers(item, format!("{at}/{k}"), out);
            }
        }
        Value::Object(map) => {
            for (key, item) in map {
                let escaped = key.replace('~', "~0").replace('/', "~1");
                pointers(item, format!("{at}/{escaped}"), out);
            }
        }
        _ => {}
    }
}

/// A string no real input holds, standing where a raw token goes once the tree is text.
const TOKEN_MARK: &str = "\u{1}token\u{1}";

/// The text of `root` with `edits` applied; raw tokens are spliced into the text.
pub fn apply_json(root: &Value, edits: &[JsonEdit]) -> String {
    let mut v = root.clone();
    let mut tokens: Vec<&'static str> = Vec::new();
    for edit in edits {
        let mut all = Vec::new();
        pointers(&v, String::new(), &mut all);
        match edit {
            JsonEdit::Replace { node, with } => {
                let at = &all[node % all.len()];
                let old = v.pointer(at).cloned().unwrap_or(Value::Null);
                let new = match with {
                    Hostile::Number(x) => {
                        serde_json::Number::from_f64(*x).map_or(Value::Null, Value::Number)
                    }
                    Hostile::MaxU64 => Value::from(u64::MAX),
                    Hostile::Token(t) => {
                        tokens.push(*t);
                        Value::String(format!("{TOKEN_MARK}{}", tokens.len() - 1))
                    }
                    Hostile::Wrong(w) => w.clone(),
                    Hostile::Nest(depth) => {
                        (0..*depth).fold(old, |inner, _| Value::Array(vec![inner]))
                    }
                    Hostile::Repeat(n) => Value::Array(vec![old; *n]),
                };
                if let Some(slot) = v.pointer_mut(at) {
                    *slot = new;
                }
            }
            JsonEdit::Remove { node } => {
                let at = all[node % all.len()].clone();
                let Some(cut) = at.rfind('/') else { continue };
                let (parent, key) = (&at[..cut], &at[cut + 1..]);
                match v.pointer_mut(parent) {
                    Some(Value::Object(map)) => {
                        map.remove(&key.replace("~1", "/").replace("~0", "~"));
                    }
                    Some(Value::Array(items)) => {
                        if let Ok(k) = key.parse::<usize>() {
                            items.remove(k);
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    // Past serde_json's own recursion limit the tree cannot be written by it; write it by hand.
    let mut text = write(&v);
    for (k, token) in tokens.iter().enumerate() {
        text = text.replace(&format!("\"{TOKEN_MARK}{k}\""), token);
    }
    text
}

/// `v` as JSON text, without recursion limits (serde_json's writer has none either, but its
/// reader would refuse what this writes past 128 levels, which is the point).
fn write(v: &Value) -> String {
    match v {
        Value::Array(items) => {
            let inner: Vec<String> = items.iter().map(write).collect();
            format!("[{}]", inner.join(","))
        }
        Value::Object(map) => {
            let inner: Vec<String> = map
                .iter()
                .map(|(k, item)| format!("{}:{}", Value::String(k.clone()), write(item)))
                .collect();
            format!("{{{}}}", inner.join(","))
        }
        leaf => leaf.to_string(),
    }
}
