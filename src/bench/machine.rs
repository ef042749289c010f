//! The machine a results file was measured on, beside its device: the CPU (which is the GPU on
//! lavapipe), the operating system, the load average before and after the run, a warning when
//! other work was running, and the GPU's clock state where a vendor tool reports it. On a shared
//! machine a cell moves by tens of percent between runs; this says which runs to doubt.

use std::process::Command;

use serde::{Deserialize, Serialize};

/// Where and under what load a run was measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchMachine {
    /// The CPU's model name (`/proc/cpuinfo`), or "unknown".
    pub cpu_model: String,
    /// Logical CPUs the process may run on.
    pub cpus: usize,
    /// The operating system and its kernel release, e.g. "linux 6.1.0-18-amd64".
    pub os: String,
    /// The 1, 5 and 15 minute load averages as the run began (`/proc/loadavg`); `None` where
    /// the system does not report them.
    pub load_before: Option<[f64; 3]>,
    /// The same as the run ended; relief's own work is in it (lavapipe keeps every core busy).
    pub load_after: Option<[f64; 3]>,
    /// Why the figures may be disturbed, when the machine was busy with other work.
    pub busy: Option<String>,
    /// The GPU's clocks, power state and clock limits as `nvidia-smi` or `rocm-smi` reported
    /// them as the run began, where one of them is installed.
    pub gpu_clocks: Option<String>,
}

/// What is read as a run begins.
#[derive(Debug, Clone)]
pub struct MachineAtStart {
    load: Option<[f64; 3]>,
    gpu_clocks: Option<String>,
}

impl MachineAtStart {
    /// Reads the load and the GPU clocks now.
    pub fn read() -> MachineAtStart {
        MachineAtStart {
            load: load_average(),
            gpu_clocks: gpu_clocks(),
        }
    }

    /// The record of the run, reading the load again now that it ended.
    pub fn finish(self) -> BenchMachine {
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let load_after = load_average();
        BenchMachine {
            cpu_model: cpu_model().unwrap_or_else(|| "unknown".into()),
            cpus,
            os: os_release(),
            busy: busy(self.load, load_after, cpus),
            load_before: self.load,
            load_after,
            gpu_clocks: self.gpu_clocks,
        }
    }
}

/// Why the machine counts as busy: another process's work was running as the run began (a
/// 1-minute load above the CPUs), or more ran beside it than relief alone can make (lavapipe
/// runs a thread per CPU, so a load above the CPUs plus one as it ended).
fn busy(before: Option<[f64; 3]>, after: Option<[f64; 3]>, cpus: usize) -> Option<String> {
    let n = cpus as f64;
    let mut why = Vec::new();
    if let Some([one, ..]) = before.filter(|l| l[0] > n) {
        why.push(format!(
            "the 1-minute load average was {one:.2} on {cpus} CPUs as the run began"
        ));
    }
    if let Some([one, ..]) = after.filter(|l| l[0] > n + 1.0) {
        why.push(format!(
            "{one:.2} as it ended, more than relief's own threads make"
        ));
    }
    (!why.is_empty()).then(|| {
        format!(
            "the machine was busy: {}; times may be slow and spread",
            why.join("; ")
        )
    })
}

/// The 1, 5 and 15 minute load averages of `/proc/loadavg`'s text.
fn parse_load(text: &str) -> Option<[f64; 3]> {
    let mut words = text.split_whitespace().map(str::parse::<f64>);
    let mut next = || words.next()?.ok();
    Some([next()?, next()?, next()?])
}

fn load_average() -> Option<[f64; 3]> {
    parse_load(&std::fs::read_to_string("/proc/loadavg").ok()?)
}

/// The first `model name` of `/proc/cpuinfo`'s text.
fn parse_cpu_model(text: &str) -> Option<String> {
    text.lines()
        .filter_map(|l| l.split_once(':'))
        .find(|(key, _)| key.trim() == "model name")
        .map(|(_, value)| value.trim().to_owned())
}

fn cpu_model() -> Option<String> {
    parse_cpu_model(&std::fs::read_to_string("/proc/cpuinfo").ok()?)
}

fn os_release() -> String {
    let release = std::fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default();
    format!("{} {}", std::env::consts::OS, release.trim())
        .trim()
        .to_owned()
}

/// The GPU's clock state from the vendor's tool, where one is installed and answers.
fn gpu_clocks() -> Option<String> {
    let nvidia = [
        "--query-gpu=name,pstate,clocks.sm,clocks.max.sm,clocks.mem,power.draw,clocks_throttle_reasons.active,persistence_mode",
        "--format=csv",
    ];
    let tools: [(&str, &[&str]); 2] = [("nvidia-smi", &nvidia), ("rocm-smi", &["--showclocks"])];
    tools.iter().find_map(|(tool, args)| {
        let out = Command::new(tool).args(*args).output().ok()?;
        let text = String::from_utf8_lossy(&out.stdout).trim().to_owned();
        (out.status.success() && !text.is_empty()).then(|| format!("{tool}: {text}"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_and_cpu_model_are_read_from_procfs_text() {
        assert_eq!(
            parse_load("0.52 1.10 2.00 3/412 12345\n"),
            Some([0.52, 1.1, 2.0])
        );
        assert_eq!(parse_load("garbage"), None);
        let cpuinfo = "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel name\t: Intel(R) Xeon(R) CPU @ 2.20GHz\n";
        assert_eq!(
            parse_cpu_model(cpuinfo).as_deref(),
            Some("Intel(R) Xeon(R) CPU @ 2.20GHz")
        );
        assert_eq!(parse_cpu_model("processor: 0\n"), None);
    }

    #[test]
    fn a_load_above_the_cpus_before_or_beyond_relief_after_is_busy() {
        assert_eq!(busy(Some([0.3, 0.2, 0.1]), Some([2.5, 1.0, 0.5]), 2), None);
        let before = busy(Some([3.1, 2.0, 1.0]), Some([2.5, 1.0, 0.5]), 2).unwrap();
        assert!(before.contains("3.10 on 2 CPUs"), "{before}");
        let after = busy(Some([0.3, 0.2, 0.1]), Some([4.0, 1.0, 0.5]), 2).unwrap();
        assert!(after.contains("4.00 as it ended"), "{after}");
        assert_eq!(busy(None, None, 2), None);
    }

    #[test]
    fn this_machine_is_described() {
        let m = MachineAtStart::read().finish();
        assert!(m.cpus >= 1);
        assert!(!m.cpu_model.is_empty() && !m.os.is_empty());
    }
}
