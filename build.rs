//! With the `denoise` feature, the binaries find Open Image Denoise's libraries where they were
//! built against (`OIDN_DIR`, filled by scripts/fetch-oidn) through an rpath: no
//! LD_LIBRARY_PATH to set.

fn main() {
    println!("cargo:rerun-if-env-changed=OIDN_DIR");
    if std::env::var_os("CARGO_FEATURE_DENOISE").is_none() {
        return;
    }
    if let Some(dir) = std::env::var_os("OIDN_DIR").filter(|dir| !dir.is_empty()) {
        let lib = std::path::Path::new(&dir).join("lib");
        println!("cargo:rustc-link-arg=-Wl,-rpath,{}", lib.display());
    }
}
