//! Checks a plugin library's file before the dynamic loader maps it.
//!
//! The loader maps each loadable segment of a library straight from the file; a segment that
//! reaches past the end of a file cut short (an interrupted copy) is mapped all the same, and the
//! first touch of a page beyond the end kills the process with SIGBUS — also for a library that
//! merely sits in a plugin folder. So before a library is opened its ELF structure is read with
//! the `object` crate and every part the loader will use is checked to lie within the file:
//! the file header, the program header table, every segment's file range, the section header
//! table and every section's file range. A file that fails is one clear error naming it, and
//! nothing of it is mapped.
//!
//! Only ELF (Linux and the BSDs) is checked; other platforms' formats go to the loader as they are.

use object::elf;
use object::read::elf::{FileHeader, ProgramHeader, SectionHeader};
use object::Endianness;
use std::path::Path;

/// Largest file read for the check; a plugin library is a few MiB.
pub const MAX_LIBRARY_BYTES: u64 = 1 << 30;

/// Why a library's file is not a whole ELF shared library, in one line; `Ok` if it is one, or if
/// this platform's libraries are not ELF.
pub fn check_library_file(path: &Path) -> Result<(), String> {
    if !cfg!(all(unix, not(target_vendor = "apple"))) {
        return Ok(());
    }
    let data = crate::limits::read_limited(path, MAX_LIBRARY_BYTES, "plugin library")
        .map_err(|e| format!("cannot read: {e}"))?;
    check_elf_bytes(&data)
}

/// [`check_library_file`] on the file's bytes.
pub fn check_elf_bytes(data: &[u8]) -> Result<(), String> {
    if data.len() < 4 || &data[..4] != b"\x7fELF" {
        return Err(format!(
            "not a loadable shared library (not an ELF file: {} bytes starting {:?})",
            data.len(),
            String::from_utf8_lossy(&data[..data.len().min(8)])
        ));
    }
    // e_ident[EI_CLASS], byte 4: 32- or 64-bit.
    match data.get(4) {
        Some(&elf::ELFCLASS64) => check::<elf::FileHeader64<Endianness>>(data),
        Some(&elf::ELFCLASS32) => check::<elf::FileHeader32<Endianness>>(data),
        other => Err(format!(
            "not a loadable shared library (unknown ELF class {other:?}; the file may be cut short)"
        )),
    }
}

fn check<H: FileHeader<Endian = Endianness>>(data: &[u8]) -> Result<(), String> {
    let len = data.len() as u64;
    let damaged = |what: String| {
        format!(
            "damaged or cut short library ({what}; the file has {len} bytes); was it copied \
             completely?"
        )
    };
    let header = H::parse(data).map_err(|e| damaged(format!("ELF header: {e}")))?;
    let endian = header
        .endian()
        .map_err(|e| damaged(format!("ELF header: {e}")))?;
    let e_type = header.e_type(endian);
    if e_type != elf::ET_DYN {
        return Err(format!(
            "not a loadable shared library (ELF type {e_type}, not a shared object)"
        ));
    }
    let segments = header
        .program_headers(endian, data)
        .map_err(|e| damaged(format!("program header table: {e}")))?;
    if segments.is_empty() {
        return Err(damaged("no program headers".into()));
    }
    for (i, ph) in segments.iter().enumerate() {
        let (offset, size) = ph.file_range(endian);
        if offset.checked_add(size).is_none_or(|end| end > len) {
            return Err(damaged(format!(
                "segment {i} (type {:#x}) spans bytes {offset}..{} of the file",
                ph.p_type(endian),
                offset as u128 + size as u128
            )));
        }
    }
    let sections = header
        .sections(endian, data)
        .map_err(|e| damaged(format!("section header table: {e}")))?;
    for (i, sh) in sections.iter().enumerate() {
        if let Some((offset, size)) = sh.file_range(endian) {
            if offset.checked_add(size).is_none_or(|end| end > len) {
                return Err(damaged(format!(
                    "section {i} spans bytes {offset}..{} of the file",
                    offset as u128 + size as u128
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// This test binary is an ELF file of the same machine; a shared library of the system is
    /// not guaranteed at a fixed path, so the check is exercised on the test executable's bytes
    /// with its type patched to ET_DYN (position-independent executables are ET_DYN already).
    fn own_elf() -> Vec<u8> {
        let mut data = std::fs::read(std::env::current_exe().unwrap()).unwrap();
        data[16] = elf::ET_DYN as u8;
        data[17] = 0;
        data
    }

    #[test]
    #[cfg(all(target_os = "linux", target_endian = "little"))]
    fn whole_file_passes_and_every_cut_is_refused() {
        let data = own_elf();
        check_elf_bytes(&data).unwrap();
        // Cuts at the header, in the middle and one byte short: each one refused, never a panic.
        for cut in [0, 3, 20, 63, 64, 100, data.len() / 2, data.len() - 1] {
            let e = check_elf_bytes(&data[..cut]).unwrap_err();
            assert!(
                e.contains("not an ELF file") || e.contains("cut short"),
                "cut at {cut}: {e}"
            );
        }
    }

    #[test]
    fn text_is_not_elf() {
        let e = check_elf_bytes(b"this is text").unwrap_err();
        assert!(e.contains("not a loadable shared library"), "{e}");
    }
}
