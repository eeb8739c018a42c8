#pragma once
// Numeric flags take finite numbers only. CLI11's Range lets NaN through (every comparison with NaN
// is false), and an infinite --duration or --rate is as meaningless; one check, applied to every
// numeric option of an app, so that a flag added later is covered without anyone remembering.

#include <CLI/CLI.hpp>

namespace haptex::flags {

/// A CLI11 check: a value that reads as a number must be finite ("nan", "inf", "1e999" refused,
/// with a message that names the value). Text that is no number at all is left to the option's
/// own conversion, which refuses it.
CLI::Validator FiniteNumber();

/// Adds FiniteNumber to every option of `app` and of all its subcommands whose type is a number
/// (CLI11's FLOAT, INT or UINT). Call once, after every option is added. A refused value is a
/// CLI::ValidationError from app.parse (exit code 2 in haptex and every service).
void RefuseNonFiniteNumbers(CLI::App& app);

}  // namespace haptex::flags
