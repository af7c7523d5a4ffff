//! What the commands share, in one place every command uses (as cargo's `command_prelude`):
//! reading steps, the memory limit, progress on stderr, output files, a step's results as text
//! and JSON, the paper's tables, numbers in words, and the recording options. A command file
//! imports `crate::common::*` and nothing from another command's file.

pub mod files;
pub mod loose;
pub mod memory;
pub mod progress;
pub mod record_args;
pub mod step_input;
pub mod step_out;
pub mod tables;
pub mod tables_text;
pub mod words;

pub use files::{prepare_dir, refuse_overwrite, same_file, writable};
pub use loose::LooseArgs;
pub use memory::{parse_memory_limit, MemoryLimit};
pub use progress::{progress, with_spinner};
pub use record_args::{RecordArgs, RecordTarget};
pub use step_input::{input_warning_lines, left_out_warning, read_step_input};
pub use step_out::{rename, write_pairs, StepOut};
pub use tables::{bench_source, Source};
pub use tables_text::print_text;
pub use words::{plural, thousands};
