#pragma once
// Running gnuplot on a script without letting user text become gnuplot code. Paths never appear in
// a script: gnuplot runs inside the folder that holds the plot, and the script names its files
// relative to it with fixed names. Text that must appear (a title) goes through GnuplotLabel.

#include <string>
#include <string_view>

namespace haptex::launch {

/// Runs `gnuplot SCRIPT` (no shell) with `dir` as its working folder; `script` is relative to
/// `dir`, and its stderr goes to dir/SCRIPT.log (removed on success). Returns an error text, empty
/// on success.
std::string RunGnuplot(const std::string& dir, const std::string& script);

/// `text` as a single-quoted gnuplot string that cannot end early or run anything: letters, digits,
/// space and - _ . , : ; ( ) [ ] + = / % are kept, any other byte (quotes, backquotes, backslashes,
/// '@', '!', control characters, non-ASCII) becomes '_'; at most 80 bytes.
std::string GnuplotLabel(std::string_view text);

}  // namespace haptex::launch
