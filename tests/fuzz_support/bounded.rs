//! Running one parser call under the fuzz tests' three bounds: it returns (no panic), within a
//! time limit (no hang), and holding at most a byte cap at once (no allocation driven by a
//! size the file claims rather than the bytes it has).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc;
use std::time::Duration;

use super::alloc_cap;

/// What one parser call may take.
#[derive(Debug, Clone, Copy)]
pub struct Bounds {
    /// Wall-clock time (debug build, two busy cores: generous, a hang is forever).
    pub time: Duration,
    /// Bytes held at once on the parser's thread.
    pub bytes: usize,
}

impl Bounds {
    /// The bounds for a parser fed an input of `input_len` bytes: 10 s, and 32 MiB plus 64 bytes
    /// for every byte of input (so a real file of a few KiB may decode to a few hundred KiB of
    /// pixels, while a 100-byte file claiming a gigapixel image is held to 32 MiB).
    pub fn for_input(input_len: usize) -> Bounds {
        Bounds {
            time: Duration::from_secs(10),
            bytes: (32 << 20) + 64 * input_len,
        }
    }
}

/// Runs `parse` on a thread of its own and returns its result, or why it broke a bound.
pub fn run_bounded<T: Send + 'static>(
    bounds: Bounds,
    parse: impl FnOnce() -> T + Send + 'static,
) -> Result<T, String> {
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("bounded-parse".into())
        .spawn(move || {
            alloc_cap::reset();
            let out = catch_unwind(AssertUnwindSafe(parse));
            let _ = tx.send((out, alloc_cap::peak()));
        })
        .expect("spawns a thread");
    match rx.recv_timeout(bounds.time) {
        Err(_) => Err(format!("did not return within {:?}", bounds.time)),
        Ok((Err(panic), _)) => {
            let why = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(format!("panicked: {why}"))
        }
        Ok((Ok(_), peak)) if peak > bounds.bytes => Err(format!(
            "held {peak} bytes at once, over the cap of {} bytes",
            bounds.bytes
        )),
        Ok((Ok(out), _)) => Ok(out),
    }
}
