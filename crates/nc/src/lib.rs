//! NC programs: Fanuc/ISO G-code with Custom Macro B, LinuxCNC and GRBL
//! dialects — parse, interpret, write.
//!
//! Three named stages, each a plain value:
//! 1. [`parse()`]: text to [`Program`], the program model with byte spans. It
//!    evaluates nothing and never fails: what it cannot read becomes a
//!    located [`Diagnostic`].
//! 2. [`interp::run`]: program to [`kezuri_geom::Toolpath`], running macros,
//!    subprograms and modal calls like a Fanuc control does.
//! 3. [`write`](mod@write): toolpath to text in a dialect.
//!
//! `nc` knows nothing of cutters and does no I/O: subprogram libraries, the
//! clock and `DPRNT` output go through [`interp::Settings`],
//! [`interp::Library`] and [`interp::Outcome`].
//!
//! # Example
//! ```
//! use kezuri_nc::{interp, parse, Program, SourceFile, Sources};
//! let mut sources = Sources::default();
//! let text = "O0001\n#1=10.\nG01 X#1 Y[#1/2] F600.\nM30\n";
//! let file = sources.add(SourceFile::new("demo.nc", text));
//! let mut program = Program::default();
//! let diagnostics = parse(&mut program, file, text);
//! assert!(diagnostics.is_empty());
//! let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &interp::Settings::default());
//! assert!(outcome.completed);
//! assert_eq!(outcome.toolpath.moves[0].end.y, 5.0);
//! ```

#![warn(missing_docs)]

pub mod ast;
pub mod detect;
mod dialect;
mod error;
pub mod interp;
mod number;
pub mod offsets;
mod paged;
mod parse;
pub mod probe_plan;
pub mod rewrite;
pub mod rml;
pub mod source;
pub mod texture_macro;
pub mod thermal_plan;
pub mod write;

pub use ast::Program;
pub use detect::{detect, detect_forgetting, Detected};
pub use dialect::Dialect;
pub use error::{Error, ErrorKind, Place};
pub use paged::Paged;
pub use parse::{comments, comments_forgetting, parse, parse_as, parse_counting, Comments};
pub use source::{Diagnostic, Severity, SourceFile, Sources, Span};
