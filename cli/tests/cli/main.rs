//! The command-line tool's tests, one binary: the commands run as a user
//! would, their outputs read back, bad inputs refused, and every command of
//! the README and the guide run as written.

mod bad_input;
mod cli;
mod readme;
