//! Finds libsscape: SSCAPE_LIB_DIR (the folder holding libsscape.so) if set, else pkg-config's
//! `sscape` (the sscape.pc that `cmake --install` writes), else the linker's default search path.
//! No dependencies: pkg-config is run as a command.
use std::env;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=SSCAPE_LIB_DIR");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    if let Ok(dir) = env::var("SSCAPE_LIB_DIR") {
        println!("cargo:rustc-link-search=native={}", dir);
        println!("cargo:rustc-link-lib=dylib=sscape");
        return;
    }
    if let Ok(output) = Command::new("pkg-config").args(["--libs", "sscape"]).output() {
        if output.status.success() {
            let flags = String::from_utf8_lossy(&output.stdout).into_owned();
            for flag in flags.split_whitespace() {
                if let Some(dir) = flag.strip_prefix("-L") {
                    println!("cargo:rustc-link-search=native={}", dir);
                } else if let Some(lib) = flag.strip_prefix("-l") {
                    println!("cargo:rustc-link-lib=dylib={}", lib);
                }
            }
            return;
        }
    }
    println!("cargo:warning=libsscape not found through SSCAPE_LIB_DIR or pkg-config; linking -lsscape from the default path");
    println!("cargo:rustc-link-lib=dylib=sscape");
}
