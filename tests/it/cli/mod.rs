//! The command line as a user runs it: success paths write whole files; bad input gives one error line naming
//! the file and the problem, a non-zero exit, and no output file. A file per concern: `gen` and `info`
//! (`gen_info`), `render`, `compare` and `soak` (`render`), the CPU models' `curve` and `composite` (`models`), the
//! help pages, completions and flags (`help`).

mod gen_info;
mod help;
mod models;
mod render;
