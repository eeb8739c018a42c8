#pragma once
// Checks every field of a text-format message by its kind, so a field the schema gains later is
// checked too: numbers finite, enum values defined, strings bounded, valid UTF-8 and free of
// control characters. The loaders add each message's own rules (ranges, names, references).

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/message.h>

#include "libs/scene/text_proto.h"

namespace haptex::scene {

/// The longest string any field may hold: paths, addresses, citations and notes fit easily.
inline constexpr std::size_t kMaxStringBytes = 4096;

/// Every field of `message` and its sub-messages: float and double finite; enum values among
/// those the enum defines (text format takes any number); strings at most kMaxStringBytes, valid
/// UTF-8 and without control characters other than tab and newline. Each problem at its field,
/// named by its path from `message` (e.g. "cloth.stand_position_w_m.x"). A loader's own rules
/// leave values that are not numbers to this check (one issue per field).
/// `max_bytes` gives some string fields, by full name ("haptex.v1.Scene.name"), a smaller bound.
void CheckEveryField(const google::protobuf::Message& message, const FieldLocator& where,
                     std::vector<TextIssue>* issues, const std::map<std::string, std::size_t>& max_bytes = {});

/// Whether `text` passes CheckEveryField's string rules (bounded, UTF-8, no control characters but
/// tab and newline): the loaders apply a field's own rules only to such text, so that one field
/// gets one issue.
bool IsWellFormedText(std::string_view text);

/// Sorts issues by line and column (stable), the order in which a reader meets them.
void SortByLocation(std::vector<TextIssue>* issues);

/// Whether `text` is valid UTF-8 (no overlong forms, no surrogates, at most U+10FFFF).
bool IsValidUtf8(std::string_view text);

/// Whether `text` is a plain name of at most `max_bytes`: ASCII letters, digits, '_', '-' and '.',
/// not starting with '.' (so never a path, "." or "..").
bool IsPlainName(std::string_view text, std::size_t max_bytes);

}  // namespace haptex::scene
