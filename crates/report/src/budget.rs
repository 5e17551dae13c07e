//! The memory a run may use: the machine's (what /proc/meminfo and the
//! cgroup allow) or the figure the user gives (`--max-memory`), and sizes
//! for a person.

/// Bytes per GiB.
pub const GIB: f64 = (1u64 << 30) as f64;

/// The memory a run may use, and where that figure comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    pub bytes: u64,
    /// "--max-memory", "available" (MemAvailable), "total" (MemTotal) or
    /// "cgroup limit".
    pub source: &'static str,
}

/// The budget: `max_memory` (the user's `--max-memory`) if given, else the
/// machine's memory; `None` when neither is known (then nothing is refused).
pub fn budget(max_memory: Option<u64>) -> Option<Budget> {
    match max_memory {
        None | Some(0) => machine_memory(),
        Some(bytes) => Some(Budget {
            bytes,
            source: "--max-memory",
        }),
    }
}

/// The machine's memory: `MemAvailable` of /proc/meminfo (what can be had
/// without swapping), else `MemTotal`, lowered to the cgroup's limit when one
/// is set (containers).
pub fn machine_memory() -> Option<Budget> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let field = |name: &str| -> Option<u64> {
        meminfo.as_deref()?.lines().find_map(|l| {
            let rest = l.strip_prefix(name)?.strip_prefix(':')?;
            let kb: u64 = rest.trim().trim_end_matches("kB").trim().parse().ok()?;
            Some(kb * 1024)
        })
    };
    let machine = field("MemAvailable")
        .map(|bytes| Budget {
            bytes,
            source: "available",
        })
        .or_else(|| {
            field("MemTotal").map(|bytes| Budget {
                bytes,
                source: "total",
            })
        });
    let cgroup = [
        "/sys/fs/cgroup/memory.max",
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",
    ]
    .iter()
    .find_map(|p| std::fs::read_to_string(p).ok()?.trim().parse::<u64>().ok());
    match (machine, cgroup) {
        (Some(m), Some(c)) if c < m.bytes => Some(Budget {
            bytes: c,
            source: "cgroup limit",
        }),
        (None, Some(c)) if c < u64::MAX / 2 => Some(Budget {
            bytes: c,
            source: "cgroup limit",
        }),
        (m, _) => m,
    }
}

/// Parses a size: a number of bytes, or with a unit `K`, `M`, `G`, `T`
/// (powers of 1024; `GiB`, `GB`, `g` are the same), e.g. `64G`, `1.5T`,
/// `500MiB`.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let value: f64 = number.trim().parse().map_err(|_| {
        format!("expected a size like 64G, 500M or 1.5T (powers of 1024), got \"{text}\"")
    })?;
    let scale = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kb" | "kib" => 1024.0,
        "m" | "mb" | "mib" => 1024.0 * 1024.0,
        "g" | "gb" | "gib" => GIB,
        "t" | "tb" | "tib" => GIB * 1024.0,
        _ => {
            return Err(format!(
                "unknown unit \"{unit}\" in \"{text}\"; use K, M, G or T (powers of 1024)"
            ))
        }
    };
    let bytes = value * scale;
    if !(1.0..1.8e19).contains(&bytes) {
        return Err(format!("expected a positive size, got \"{text}\""));
    }
    Ok(bytes as u64)
}

/// `bytes` for a person: "850 MiB", "1.5 GiB", "41 GiB", "3.0 TiB".
pub fn human(bytes: f64) -> String {
    const UNITS: [&str; 3] = ["GiB", "TiB", "PiB"];
    if bytes < 1024.0 * 1024.0 {
        return format!("{:.0} KiB", (bytes / 1024.0).ceil());
    }
    if bytes < GIB {
        return format!("{:.0} MiB", bytes / 1024.0 / 1024.0);
    }
    let mut v = bytes / GIB;
    for (i, unit) in UNITS.iter().enumerate() {
        if v < 1024.0 || i + 1 == UNITS.len() {
            return if v >= 1e4 {
                format!("{v:.1e} {unit}")
            } else if v >= 10.0 {
                format!("{v:.0} {unit}")
            } else {
                format!("{v:.1} {unit}")
            };
        }
        v /= 1024.0;
    }
    unreachable!()
}
