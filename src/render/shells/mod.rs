//! Prism shells on the device: a relief mesh's shell (built on the CPU by `crate::shells`)
//! uploaded for the surface pass's `:shells` pipelines, and what `--explain` says of it.

pub(in crate::render) mod shell_upload;
