//! The machine's peak floating-point rate and memory bandwidth for `decohesion bench`, read at
//! run time, each figure with its source: peak = cores × clock × f64 lanes per FMA × FMA units
//! × 2 flops (an FMA is two), for the kernels' instruction set; a STREAM-like triad for the
//! bandwidth.

use decohesion_physics::kernels::simd::Isa;
use std::collections::BTreeSet;
use std::time::Instant;

/// A figure and where it comes from.
pub struct Figure<T> {
    pub value: T,
    pub source: String,
}

/// The peak double-precision rate of the cores the bench uses, with its factors.
pub struct Peak {
    pub cores: Figure<usize>,
    pub ghz: Figure<f64>,
    pub lanes: Figure<usize>,
    pub units: Figure<usize>,
}

impl Peak {
    /// cores × GHz × lanes × units × 2 [GFLOP/s].
    pub fn gflops(&self) -> f64 {
        (self.cores.value * self.lanes.value * self.units.value * 2) as f64 * self.ghz.value
    }

    /// The factors of [`Peak::gflops`], one line.
    pub fn describe(&self) -> String {
        format!(
            "{} cores ({}) × {:.3} GHz ({}) × {} f64 lanes per FMA ({}) × {} FMA units ({}) × 2 flops = {:.1} GFLOP/s",
            self.cores.value,
            self.cores.source,
            self.ghz.value,
            self.ghz.source,
            self.lanes.value,
            self.lanes.source,
            self.units.value,
            self.units.source,
            self.gflops()
        )
    }
}

/// The fields `key` of every processor block of /proc/cpuinfo.
fn cpuinfo_fields(cpuinfo: &str, key: &str) -> Vec<String> {
    cpuinfo
        .lines()
        .filter_map(|l| l.split_once(':'))
        .filter(|(k, _)| k.trim() == key)
        .map(|(_, v)| v.trim().to_string())
        .collect()
}

/// The peak of `threads` threads on this machine with the kernels built for `isa`.
pub fn peak(threads: usize, isa: Isa) -> Peak {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    // Physical cores: distinct (physical id, core id) pairs; SMT siblings share an FMA unit.
    let pairs: BTreeSet<(String, String)> = cpuinfo_fields(&cpuinfo, "physical id")
        .into_iter()
        .zip(cpuinfo_fields(&cpuinfo, "core id"))
        .collect();
    let (machine, source) = if pairs.is_empty() {
        (
            std::thread::available_parallelism().map_or(1, |n| n.get()),
            "logical CPUs, /proc/cpuinfo unreadable".to_string(),
        )
    } else {
        (pairs.len(), "/proc/cpuinfo core ids".to_string())
    };
    let cores = Figure {
        value: threads.min(machine),
        source: format!("{source}: {machine} on the machine, {threads} threads used"),
    };
    let ghz = clock(&cpuinfo);
    let family = cpuinfo_fields(&cpuinfo, "cpu family")
        .first()
        .and_then(|f| f.parse::<u32>().ok());
    let amd = cpuinfo_fields(&cpuinfo, "vendor_id")
        .first()
        .is_some_and(|v| v == "AuthenticAMD");
    let lanes = match isa {
        // Zen 4 (family 19h) executes a 512-bit FMA in two 256-bit halves.
        Isa::Avx512 if amd && family.is_some_and(|f| f < 0x1a) => Figure {
            value: 4,
            source: format!(
                "avx512 build: 8 lanes, run as two 256-bit halves by this AMD family {:x}h",
                family.unwrap_or(0)
            ),
        },
        _ => Figure {
            value: isa.f64_lanes().max(2),
            source: format!(
                "{} build{}",
                isa.name(),
                if isa == Isa::Portable {
                    ": SSE2, no FMA, counted as 2 lanes"
                } else {
                    ""
                }
            ),
        },
    };
    let units = Figure {
        value: 2,
        source: "two FMA pipes per core, as on every x86 core since Haswell and Zen (not readable from cpuid)".into(),
    };
    Peak {
        cores,
        ghz,
        lanes,
        units,
    }
}

/// The clock: the cpufreq maximum if the kernel exposes it, else /proc/cpuinfo's "cpu MHz"
/// (the nominal clock under a hypervisor; turbo above it would lower the share of peak).
fn clock(cpuinfo: &str) -> Figure<f64> {
    let path = "/sys/devices/system/cpu/cpu0/cpufreq/cpuinfo_max_freq";
    if let Some(khz) = std::fs::read_to_string(path)
        .ok()
        .and_then(|s| s.trim().parse::<f64>().ok())
    {
        return Figure {
            value: khz * 1e-6,
            source: path.to_string(),
        };
    }
    let mhz = cpuinfo_fields(cpuinfo, "cpu MHz")
        .iter()
        .filter_map(|m| m.parse::<f64>().ok())
        .fold(0.0, f64::max);
    if mhz > 0.0 {
        Figure {
            value: mhz * 1e-3,
            source: "/proc/cpuinfo cpu MHz".into(),
        }
    } else {
        Figure {
            value: f64::NAN,
            source: "no cpufreq, no /proc/cpuinfo cpu MHz".into(),
        }
    }
}

/// Memory bandwidth of one thread by a triad a = b + s·c on three 64 MiB arrays (twice the
/// size of a large L3), best of 5, counting 3 × 8 bytes per element (a write-allocate would
/// add 8 more) [GB/s].
pub fn triad_gbs() -> f64 {
    let n = 8 << 20;
    let (b, c) = (vec![1.0f64; n], vec![2.0f64; n]);
    let mut a = vec![0.0f64; n];
    let mut best = f64::INFINITY;
    for k in 0..5 {
        let s = 1.0 + k as f64;
        let t = Instant::now();
        for ((a, b), c) in a.iter_mut().zip(&b).zip(&c) {
            *a = b + s * c;
        }
        best = best.min(t.elapsed().as_secs_f64());
        std::hint::black_box(&a);
    }
    (3 * 8 * n) as f64 / best * 1e-9
}
