//! Resource limits: what a request may ask of the machine before it is refused with an error
//! that states the limit and the request, instead of an abort on a failed allocation, a read
//! that never ends or a thread pool that takes minutes to start.
//!
//! | limit | value | why |
//! | --- | --- | --- |
//! | image size | width × height × [`BYTES_PER_PIXEL`] ≤ half the available memory | the films, the final image and the outputs live at once |
//! | samples per pixel | ≤ [`MAX_SPP`] (2^24) | the pass list of a fixed budget grows with it; an f64 pixel sum of 2^24 samples still keeps 29 bits |
//! | threads | ≤ [`max_threads`]: 16 per core, at least 64 | more only adds start-up time and memory |
//! | scene file | ≤ [`SCENE_FILE_MAX_BYTES`] (64 MiB) | a scene description is text a person writes |
//! | spectrum table (CSV) | ≤ [`TABLE_FILE_MAX_BYTES`] (64 MiB) | a measured table is kilobytes |
//! | luminaire (IES, EULUMDAT, tilt) | ≤ [`LUMINAIRE_FILE_MAX_BYTES`] (64 MiB) | a measured luminaire is kilobytes |
//! | mesh file | ≤ [`mesh_file_max_bytes`]: 1/16 of the available memory, 64 MiB … 4 GiB | parsing and the BVH take many times the text |
//! | triangles of one mesh | ≤ [`max_triangles`]: half the available memory / [`BYTES_PER_TRIANGLE`] | indices, vertices and BVH |
//!
//! "Available memory" is Linux's `MemAvailable` (memory that can be had without swapping); on
//! other systems, or when `/proc/meminfo` cannot be read, [`FALLBACK_MEMORY_BYTES`].

use std::io::Read;
use std::path::Path;

/// Bytes one image pixel costs across a render: the pixel film (32), the splat film (24, 48
/// if widened), the final XYZ image (24), its RGB copy (24), the EXR channels (24) and PNG
/// bytes. Measured: a 1024×1024 BDPT render of `scenes/caustic.ron` at 1 spp has a peak resident
/// set of 129.4 MB against 6.6 MB at 32×24, 120 bytes per pixel; the rest is headroom for the
/// per-strategy debug images and a wider splat film.
pub const BYTES_PER_PIXEL: u64 = 256;

/// Most samples per pixel one render may ask for.
pub const MAX_SPP: u64 = 1 << 24;

/// Largest scene description file read.
pub const SCENE_FILE_MAX_BYTES: u64 = 64 << 20;

/// Largest spectrum table (CSV) read.
pub const TABLE_FILE_MAX_BYTES: u64 = 64 << 20;

/// Largest luminaire file (IES, EULUMDAT, IES tilt file) read: real ones are kilobytes.
pub const LUMINAIRE_FILE_MAX_BYTES: u64 = 64 << 20;

/// Bytes one triangle costs once loaded: indices (12), up to three vertices with normals and
/// uvs (3 × 32, shared in practice), the BVH's primitive reference and node share (~40).
pub const BYTES_PER_TRIANGLE: u64 = 160;

/// Memory assumed available when the system does not say.
pub const FALLBACK_MEMORY_BYTES: u64 = 4 << 30;

/// Memory that can be had without swapping, in bytes (`MemAvailable` of `/proc/meminfo`).
pub fn available_memory_bytes() -> u64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| parse_mem_available(&text))
        .unwrap_or(FALLBACK_MEMORY_BYTES)
}

/// `MemAvailable:  12345 kB` → bytes.
fn parse_mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?;
    let mut it = line.split_whitespace();
    let n: u64 = it.next()?.parse().ok()?;
    let unit = match it.next() {
        Some("kB") | Some("KB") => 1024,
        None => 1,
        Some(_) => return None,
    };
    n.checked_mul(unit)
}

/// `1234567890` → `"1.15 GiB"`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["bytes", "KiB", "MiB", "GiB", "TiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} bytes")
    } else {
        format!("{v:.2} {}", UNITS[u])
    }
}

/// Refuse an image whose films would not fit in half of `available` bytes.
pub fn check_image_size_with(width: u64, height: u64, available: u64) -> Result<(), String> {
    let pixels = width.saturating_mul(height);
    let need = pixels.saturating_mul(BYTES_PER_PIXEL);
    let limit = available / 2;
    if need > limit {
        let max_side = ((limit / BYTES_PER_PIXEL) as f64).sqrt() as u64;
        return Err(format!(
            "an image of {width}×{height} pixels needs about {} for its films, more than the \
             limit of {} (half the available memory of {}); the largest square image is about \
             {max_side}×{max_side}",
            human_bytes(need),
            human_bytes(limit),
            human_bytes(available)
        ));
    }
    Ok(())
}

/// [`check_image_size_with`] against this machine's available memory.
pub fn check_image_size(width: u64, height: u64) -> Result<(), String> {
    check_image_size_with(width, height, available_memory_bytes())
}

/// Refuse more than [`MAX_SPP`] samples per pixel; `what` names the option (`--spp`).
pub fn check_spp(spp: u64, what: &str) -> Result<(), String> {
    if spp > MAX_SPP {
        return Err(format!(
            "{what} {spp} is more than the limit of {MAX_SPP} samples per pixel"
        ));
    }
    Ok(())
}

/// Most worker threads a render may start: 16 per core, at least 64.
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    (cores * 16).max(64)
}

/// Refuse a thread count of 0 or above [`max_threads`].
pub fn check_threads(threads: usize) -> Result<(), String> {
    let max = max_threads();
    if threads == 0 {
        return Err("--threads must be at least 1".into());
    }
    if threads > max {
        return Err(format!(
            "--threads {threads} is more than the limit of {max} (16 per core of the {} this \
             machine has, at least 64)",
            std::thread::available_parallelism().map_or(1, |n| n.get())
        ));
    }
    Ok(())
}

/// Clap value parser for `--threads`: a positive integer within [`check_threads`].
pub fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a thread count (a positive integer)"))?;
    check_threads(n)?;
    Ok(n)
}

/// Clap value parser for `--spp` and `--pass-spp`: a positive integer within [`check_spp`].
pub fn parse_spp(s: &str) -> Result<u32, String> {
    let n: u64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a sample count (a positive integer)"))?;
    if n == 0 {
        return Err("the sample count must be at least 1".into());
    }
    check_spp(n, "the sample count")?;
    Ok(n as u32)
}

/// Largest mesh file read: 1/16 of the available memory, clamped to 64 MiB … 4 GiB.
pub fn mesh_file_max_bytes() -> u64 {
    (available_memory_bytes() / 16).clamp(64 << 20, 4 << 30)
}

/// Most triangles one mesh may have: half the available memory at [`BYTES_PER_TRIANGLE`] each.
pub fn max_triangles() -> u64 {
    available_memory_bytes() / 2 / BYTES_PER_TRIANGLE
}

/// Read the whole file at `path`, refusing it if it holds more than `max_bytes`. A regular file
/// is judged by its size before anything is read; a device, pipe or file that grows (for
/// example `/dev/zero`) is read no further than `max_bytes + 1`. `what` names the kind of file
/// in the error ("scene file").
pub fn read_limited(path: &Path, max_bytes: u64, what: &str) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let too_big = |size: String| {
        std::io::Error::other(format!(
            "{size} is larger than the limit of {} for a {what}",
            human_bytes(max_bytes)
        ))
    };
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(std::io::Error::other(format!(
            "is a directory, not a {what}"
        )));
    }
    if meta.is_file() && meta.len() > max_bytes {
        return Err(too_big(human_bytes(meta.len())));
    }
    let mut bytes = Vec::with_capacity(if meta.is_file() {
        meta.len() as usize
    } else {
        0
    });
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_big("its content".into()));
    }
    Ok(bytes)
}

/// [`read_limited`] for text: the bytes must be UTF-8.
pub fn read_text_limited(path: &Path, max_bytes: u64, what: &str) -> std::io::Result<String> {
    let bytes = read_limited(path, max_bytes, what)?;
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("is not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    // The parser takes the kB figure of a real /proc/meminfo layout; exact, integer arithmetic.
    #[test]
    fn mem_available_is_parsed_in_bytes() {
        let text = "MemTotal:       25165824 kB\nMemFree:  100 kB\nMemAvailable:   20971520 kB\n";
        assert_eq!(parse_mem_available(text), Some(20 << 30));
        assert_eq!(parse_mem_available("MemTotal: 5 kB\n"), None);
    }

    // 65536² pixels at 256 bytes each is 1 TiB: refused on a 24 GiB machine, with both numbers
    // in the message; 1920×1080 (530 MB) passes.
    #[test]
    fn image_size_limit_names_request_and_limit() {
        let avail = 24 << 30;
        let e = check_image_size_with(65536, 65536, avail).unwrap_err();
        assert!(
            e.contains("65536×65536") && e.contains("1.00 TiB") && e.contains("12.00 GiB"),
            "{e}"
        );
        assert!(check_image_size_with(1920, 1080, avail).is_ok());
    }

    // u32::MAX spp is refused; the limit itself is allowed.
    #[test]
    fn spp_limit() {
        let e = check_spp(u32::MAX as u64, "--spp").unwrap_err();
        assert!(e.contains("4294967295") && e.contains("16777216"), "{e}");
        assert!(check_spp(MAX_SPP, "--spp").is_ok());
    }

    // 100000 threads is refused naming both numbers; 1 passes; 0 is refused.
    #[test]
    fn thread_limit() {
        let e = check_threads(100_000).unwrap_err();
        assert!(
            e.contains("100000") && e.contains(&max_threads().to_string()),
            "{e}"
        );
        assert!(check_threads(1).is_ok());
        assert!(check_threads(0).is_err());
    }

    // /dev/zero never ends: the read stops one byte past the limit and says so.
    #[test]
    fn endless_file_is_cut_at_the_limit() {
        let e = read_limited(Path::new("/dev/zero"), 1 << 16, "scene file").unwrap_err();
        assert!(
            e.to_string().contains("64.00 KiB") && e.to_string().contains("scene file"),
            "{e}"
        );
    }

    // A regular file larger than the limit is refused by its size; one within it is read whole.
    #[test]
    fn regular_file_limit() {
        let dir = std::env::temp_dir().join(format!("spectrace-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("ten.txt");
        std::fs::write(&f, b"0123456789").unwrap();
        assert_eq!(read_limited(&f, 10, "mesh file").unwrap().len(), 10);
        let e = read_limited(&f, 9, "mesh file").unwrap_err();
        assert!(
            e.to_string().contains("10 bytes") && e.to_string().contains("9 bytes"),
            "{e}"
        );
        let e = read_limited(&dir, 9, "mesh file").unwrap_err();
        assert!(e.to_string().contains("directory"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
