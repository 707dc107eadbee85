// Text from a file name, a file, a log or the network, made safe to show on
// a terminal or to quote into another program's language: it can carry no
// control sequence and no line break.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace odoloc::output {

// `text` with printable ASCII and well-formed UTF-8 kept as they are, and as
// escapes of plain ASCII: every other byte (C0 controls, including the line
// break and the tab, DEL, bytes that are not well-formed UTF-8) as \xHH,
// and the code points a terminal would act on or that reorder what is shown
// (the C1 controls U+0080..U+009F, the bidirectional formatting characters
// U+061C, U+200E, U+200F, U+202A..U+202E, U+2066..U+2069, the line and
// paragraph separators U+2028, U+2029) as \u{XXXX}. Printable text is
// returned unchanged.
std::string printable(std::string_view text);

// printable() of at most the first `longest` bytes of `text`, then "..."
// when it was longer: a value quoted in an error message.
std::string printable_excerpt(std::string_view text, std::size_t longest = 40);

}  // namespace odoloc::output
