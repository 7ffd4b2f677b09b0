#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

mod atomic;
pub mod lock;

pub use atomic::{
    COMMIT_RECORD, Temporary, commit_files, commit_section, remove_temporaries_and_exit,
    replace_dir, set_interrupt_note, set_stale_notifier, sweep_stale, sweep_stale_once,
    write_file_atomically,
};
