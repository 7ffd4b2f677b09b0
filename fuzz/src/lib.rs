//! Helpers shared by the fuzz targets: the readers under test take paths, so each input is
//! written to a per-process scratch file first.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// A per-process scratch directory under the system temp dir (removed by nobody: it holds a
/// handful of small files and a copy of `experiments/`, about 150 KB).
pub fn scratch_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("sinsbench-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("create the fuzz scratch directory");
        d
    })
}

/// Write `data` to `name` in the scratch directory and return the path.
pub fn write_input(name: &str, data: &[u8]) -> PathBuf {
    write_at(&scratch_dir().join(name), data)
}

/// Write `data` to `path` (overwriting) and return it.
pub fn write_at(path: &Path, data: &[u8]) -> PathBuf {
    std::fs::write(path, data).expect("write the fuzz input");
    path.to_owned()
}

/// A copy of the repository's `experiments/` in the scratch directory, so that an experiment
/// or report configuration written there resolves its relative references (truth parameters,
/// scheme and pattern tables) to the shipped files, and nothing the fuzzer writes can touch the
/// checkout.
pub fn experiments_copy() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments");
        let dst = scratch_dir().join("experiments");
        copy_tree(&src, &dst).expect("copy experiments/ into the scratch directory");
        dst
    })
}

fn copy_tree(src: &Path, dst: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dst)?;
    for e in std::fs::read_dir(src)? {
        let e = e?;
        let to = dst.join(e.file_name());
        if e.file_type()?.is_dir() {
            copy_tree(&e.path(), &to)?;
        } else {
            std::fs::copy(e.path(), &to)?;
        }
    }
    Ok(())
}

/// The error's message must render (Display walks paths, rows and keys).
pub fn render<E: std::fmt::Display>(e: &E) -> usize {
    e.to_string().len()
}

/// Run one input the way the CLI does. libfuzzer-sys makes every panic abort, even one a
/// library would catch (none does now: the Parquet reader checks what the third-party decoder
/// would panic on before calling it). Here a panic only records its message; a panic that
/// escapes `body` is printed and aborts (a crash), one caught inside is not.
pub fn guard(body: impl FnOnce()) {
    use std::cell::RefCell;
    use std::sync::Once;
    thread_local! {
        static LAST_PANIC: RefCell<String> = const { RefCell::new(String::new()) };
    }
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        // Each panic site once on stderr (caught ones included, so that the log shows what the
        // library had to catch), every message kept for the abort below.
        static SEEN: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
        std::panic::set_hook(Box::new(|info| {
            let msg = format!("{info}");
            let site = info.location().map(|l| l.to_string()).unwrap_or_default();
            if let Ok(mut seen) = SEEN.lock()
                && !seen.contains(&site)
            {
                eprintln!("note: first panic at {site} (caught unless an abort follows): {msg}");
                seen.push(site);
            }
            LAST_PANIC.with(|p| *p.borrow_mut() = msg);
        }))
    });
    if std::panic::catch_unwind(std::panic::AssertUnwindSafe(body)).is_err() {
        let msg = LAST_PANIC.with(|p| p.borrow().clone());
        eprintln!("panic escaped to the caller: {msg}");
        std::process::abort();
    }
}

/// Opens the dataset at `path` and streams every batch; errors are rendered (a panic, hang or
/// runaway allocation is the finding). Shared by `dataset_csv` and `dataset_parquet`.
#[cfg(feature = "data")]
pub fn read_dataset(path: &Path) {
    let mut reader = match sins_data::DatasetReader::open(path) {
        Ok(r) => r,
        Err(e) => {
            render(&e);
            return;
        }
    };
    let _ = reader.info().meta.sample_interval_s();
    let mut batch = sins_data::SampleBatch::default();
    loop {
        match reader.next_batch_into(&mut batch) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                render(&e);
                break;
            }
        }
    }
}

/// Import `data` (written to `name`) with the description `desc_toml` into a scratch Parquet
/// file. Any error is fine; a panic, hang or runaway allocation is not.
#[cfg(feature = "data")]
pub fn import_bytes(name: &str, data: &[u8], desc_toml: &str) {
    let src = write_input(name, data);
    let desc_file = scratch_dir().join("desc.toml");
    let Ok(desc) = sins_import::Description::from_toml(desc_toml, &desc_file) else {
        return;
    };
    let out = scratch_dir().join("imported.parquet");
    let _ = sins_import::import(
        &sins_import::ImportRequest {
            source: &src,
            description: &desc,
            description_file: &desc_file,
            description_text: desc_toml,
            out: &out,
        },
        &mut |_| {},
    );
}
