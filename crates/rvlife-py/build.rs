//! The interpreter's library folder as the run-time search path of this crate's tests: the
//! stub's test links libpython (the workspace build has no `extension-module`), and Python
//! installations outside the system's folders (pyenv, conda) are not on the loader's path.

fn main() {
    let config = pyo3_build_config::get();
    if let Some(dir) = &config.lib_dir {
        println!("cargo:rustc-link-arg-tests=-Wl,-rpath,{dir}");
    }
}
