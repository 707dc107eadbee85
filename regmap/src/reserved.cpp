// The reserved words of every generated language, as data. A generated
// identifier that is one of them (or has a reserved prefix) is refused by
// check_generated_names() (names.cpp).
#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>

#include "names.hpp"

namespace odoloc::regmap {

namespace {

using std::string_view_literals::operator""sv;

// C99, C11, C17 and C23 keywords.
constexpr std::array kCKeywords = {
    "auto"sv,       "break"sv,      "case"sv,           "char"sv,
    "const"sv,      "continue"sv,   "default"sv,        "do"sv,
    "double"sv,     "else"sv,       "enum"sv,           "extern"sv,
    "float"sv,      "for"sv,        "goto"sv,           "if"sv,
    "inline"sv,     "int"sv,        "long"sv,           "register"sv,
    "restrict"sv,   "return"sv,     "short"sv,          "signed"sv,
    "sizeof"sv,     "static"sv,     "struct"sv,         "switch"sv,
    "typedef"sv,    "union"sv,      "unsigned"sv,       "void"sv,
    "volatile"sv,   "while"sv,      "_Alignas"sv,       "_Alignof"sv,
    "_Atomic"sv,    "_Bool"sv,      "_Complex"sv,       "_Generic"sv,
    "_Imaginary"sv, "_Noreturn"sv,  "_Static_assert"sv, "_Thread_local"sv,
    "_BitInt"sv,    "_Decimal32"sv, "_Decimal64"sv,     "_Decimal128"sv,
    "alignas"sv,    "alignof"sv,    "bool"sv,           "constexpr"sv,
    "false"sv,      "nullptr"sv,    "static_assert"sv,  "thread_local"sv,
    "true"sv,       "typeof"sv,     "typeof_unqual"sv,
};

// C++20 keywords, alternative tokens and identifiers with special meaning.
constexpr std::array kCppKeywords = {
    "alignas"sv,       "alignof"sv,     "and"sv,
    "and_eq"sv,        "asm"sv,         "auto"sv,
    "bitand"sv,        "bitor"sv,       "bool"sv,
    "break"sv,         "case"sv,        "catch"sv,
    "char"sv,          "char8_t"sv,     "char16_t"sv,
    "char32_t"sv,      "class"sv,       "compl"sv,
    "concept"sv,       "const"sv,       "consteval"sv,
    "constexpr"sv,     "constinit"sv,   "const_cast"sv,
    "continue"sv,      "co_await"sv,    "co_return"sv,
    "co_yield"sv,      "decltype"sv,    "default"sv,
    "delete"sv,        "do"sv,          "double"sv,
    "dynamic_cast"sv,  "else"sv,        "enum"sv,
    "explicit"sv,      "export"sv,      "extern"sv,
    "false"sv,         "float"sv,       "for"sv,
    "friend"sv,        "goto"sv,        "if"sv,
    "inline"sv,        "int"sv,         "long"sv,
    "mutable"sv,       "namespace"sv,   "new"sv,
    "noexcept"sv,      "not"sv,         "not_eq"sv,
    "nullptr"sv,       "operator"sv,    "or"sv,
    "or_eq"sv,         "private"sv,     "protected"sv,
    "public"sv,        "register"sv,    "reinterpret_cast"sv,
    "requires"sv,      "return"sv,      "short"sv,
    "signed"sv,        "sizeof"sv,      "static"sv,
    "static_assert"sv, "static_cast"sv, "struct"sv,
    "switch"sv,        "template"sv,    "this"sv,
    "thread_local"sv,  "throw"sv,       "true"sv,
    "try"sv,           "typedef"sv,     "typeid"sv,
    "typename"sv,      "union"sv,       "unsigned"sv,
    "using"sv,         "virtual"sv,     "void"sv,
    "volatile"sv,      "wchar_t"sv,     "while"sv,
    "xor"sv,           "xor_eq"sv,      "final"sv,
    "override"sv,      "import"sv,      "module"sv,
};

// Lower-case macros of the C and C++ standard headers, and the ones GCC and
// Clang predefine in their GNU dialects (-std=gnu++20 turns `linux` into 1).
constexpr std::array kLowerCaseMacros = {
    "assert"sv, "errno"sv,    "offsetof"sv, "setjmp"sv,    "va_arg"sv,   "va_copy"sv,
    "va_end"sv, "va_start"sv, "complex"sv,  "imaginary"sv, "noreturn"sv, "math_errhandling"sv,
    "stdin"sv,  "stdout"sv,   "stderr"sv,   "linux"sv,     "unix"sv,     "i386"sv,
    "major"sv,  "minor"sv,    "makedev"sv,  "isnan"sv,     "isinf"sv,    "signbit"sv,
};

// Upper-case macros of the C standard headers a firmware includes next to
// ours (stdint.h, stddef.h, limits.h, stdbool.h, stdio.h, stdlib.h).
constexpr std::array kCMacros = {
    "NULL"sv,
    "EOF"sv,
    "BUFSIZ"sv,
    "FILENAME_MAX"sv,
    "FOPEN_MAX"sv,
    "L_tmpnam"sv,
    "TMP_MAX"sv,
    "SEEK_CUR"sv,
    "SEEK_END"sv,
    "SEEK_SET"sv,
    "EXIT_FAILURE"sv,
    "EXIT_SUCCESS"sv,
    "RAND_MAX"sv,
    "MB_CUR_MAX"sv,
    "CHAR_BIT"sv,
    "CHAR_MAX"sv,
    "CHAR_MIN"sv,
    "SCHAR_MAX"sv,
    "SCHAR_MIN"sv,
    "UCHAR_MAX"sv,
    "SHRT_MAX"sv,
    "SHRT_MIN"sv,
    "USHRT_MAX"sv,
    "INT_MAX"sv,
    "INT_MIN"sv,
    "UINT_MAX"sv,
    "LONG_MAX"sv,
    "LONG_MIN"sv,
    "ULONG_MAX"sv,
    "LLONG_MAX"sv,
    "LLONG_MIN"sv,
    "ULLONG_MAX"sv,
    "MB_LEN_MAX"sv,
    "SIZE_MAX"sv,
    "PTRDIFF_MAX"sv,
    "PTRDIFF_MIN"sv,
    "SIG_ATOMIC_MAX"sv,
    "SIG_ATOMIC_MIN"sv,
    "WCHAR_MAX"sv,
    "WCHAR_MIN"sv,
    "WINT_MAX"sv,
    "WINT_MIN"sv,
    "INTPTR_MAX"sv,
    "INTPTR_MIN"sv,
    "UINTPTR_MAX"sv,
    "INTMAX_MAX"sv,
    "INTMAX_MIN"sv,
    "UINTMAX_MAX"sv,
    "INTMAX_C"sv,
    "UINTMAX_C"sv,
    "BIT"sv,
    "TRUE"sv,
    "FALSE"sv,
};

// Prefixes the C standard reserves for macros (errno.h E + digit or upper
// case, signal.h, locale.h, fenv.h, inttypes.h, stdint.h, stdatomic.h, time.h)
// and for functions (ctype.h is/to, string.h str/mem/wcs + lower case).
bool reserved_c_prefix(std::string_view id) {
  const auto next_is = [&](std::size_t at, auto pred) {
    return id.size() > at && pred(static_cast<unsigned char>(id[at])) != 0;
  };
  const auto upper_or_digit = [](int c) { return std::isupper(c) || std::isdigit(c); };
  const auto lower = [](int c) { return std::islower(c); };
  if (id.starts_with("E") && next_is(1, upper_or_digit))
    return true;
  for (const std::string_view p :
       {"LC_"sv, "SIG_"sv, "FE_"sv, "FP_"sv, "PRI"sv, "SCN"sv, "ATOMIC_"sv, "TIME_"sv,
        "MEMORY_ORDER_"sv, "DBL_"sv, "FLT_"sv, "LDBL_"sv, "TSS_"sv, "__"sv}) {
    if (id.starts_with(p))
      return true;
  }
  if (id.starts_with("SIG") && next_is(3, [](int c) { return std::isupper(c); }))
    return true;
  for (const std::string_view p : {"INT"sv, "UINT"sv}) {
    if (id.starts_with(p)) {
      for (const std::string_view s : {"_MAX"sv, "_MIN"sv, "_C"sv, "_WIDTH"sv}) {
        if (id.ends_with(s))
          return true;
      }
    }
  }
  for (const std::string_view p : {"is"sv, "to"sv}) {
    if (id.starts_with(p) && next_is(2, lower))
      return true;
  }
  for (const std::string_view p : {"str"sv, "mem"sv, "wcs"sv}) {
    if (id.starts_with(p) && next_is(3, lower))
      return true;
  }
  for (const std::string_view p :
       {"atomic_"sv, "cnd_"sv, "mtx_"sv, "thrd_"sv, "tss_"sv, "memory_order_"sv}) {
    if (id.starts_with(p))
      return true;
  }
  return false;
}

// SystemRDL 2.0 keywords and reserved words (the grammar of systemrdl-compiler).
constexpr std::array kRdlKeywords = {
    "abstract"sv,
    "accesstype"sv,
    "addressingtype"sv,
    "addrmap"sv,
    "alias"sv,
    "all"sv,
    "alternate"sv,
    "bit"sv,
    "boolean"sv,
    "bothedge"sv,
    "byte"sv,
    "compact"sv,
    "component"sv,
    "componentwidth"sv,
    "constraint"sv,
    "default"sv,
    "encode"sv,
    "enum"sv,
    "external"sv,
    "false"sv,
    "field"sv,
    "fullalign"sv,
    "hw"sv,
    "inside"sv,
    "int"sv,
    "internal"sv,
    "level"sv,
    "longint"sv,
    "mem"sv,
    "na"sv,
    "negedge"sv,
    "nonsticky"sv,
    "number"sv,
    "onreadtype"sv,
    "onwritetype"sv,
    "posedge"sv,
    "precedencetype"sv,
    "property"sv,
    "r"sv,
    "rclr"sv,
    "real"sv,
    "ref"sv,
    "reg"sv,
    "regalign"sv,
    "regfile"sv,
    "rset"sv,
    "ruser"sv,
    "rw"sv,
    "rw1"sv,
    "shortint"sv,
    "shortreal"sv,
    "signal"sv,
    "signed"sv,
    "string"sv,
    "struct"sv,
    "sw"sv,
    "this"sv,
    "true"sv,
    "type"sv,
    "unsigned"sv,
    "w"sv,
    "w1"sv,
    "wclr"sv,
    "with"sv,
    "within"sv,
    "woclr"sv,
    "woset"sv,
    "wot"sv,
    "wr"sv,
    "wset"sv,
    "wuser"sv,
    "wzc"sv,
    "wzs"sv,
    "wzt"sv,
};

// SystemVerilog (IEEE 1800-2017) keywords: PeakRDL exports the SystemRDL
// names to SystemVerilog, so they must be legal there too.
constexpr std::array kSvKeywords = {
    "accept_on"sv,
    "alias"sv,
    "always"sv,
    "always_comb"sv,
    "always_ff"sv,
    "always_latch"sv,
    "and"sv,
    "assert"sv,
    "assign"sv,
    "assume"sv,
    "automatic"sv,
    "before"sv,
    "begin"sv,
    "bind"sv,
    "bins"sv,
    "binsof"sv,
    "bit"sv,
    "break"sv,
    "buf"sv,
    "bufif0"sv,
    "bufif1"sv,
    "byte"sv,
    "case"sv,
    "casex"sv,
    "casez"sv,
    "cell"sv,
    "chandle"sv,
    "checker"sv,
    "class"sv,
    "clocking"sv,
    "cmos"sv,
    "config"sv,
    "const"sv,
    "constraint"sv,
    "context"sv,
    "continue"sv,
    "cover"sv,
    "covergroup"sv,
    "coverpoint"sv,
    "cross"sv,
    "deassign"sv,
    "default"sv,
    "defparam"sv,
    "design"sv,
    "disable"sv,
    "dist"sv,
    "do"sv,
    "edge"sv,
    "else"sv,
    "end"sv,
    "endcase"sv,
    "endchecker"sv,
    "endclass"sv,
    "endclocking"sv,
    "endconfig"sv,
    "endfunction"sv,
    "endgenerate"sv,
    "endgroup"sv,
    "endinterface"sv,
    "endmodule"sv,
    "endpackage"sv,
    "endprimitive"sv,
    "endprogram"sv,
    "endproperty"sv,
    "endspecify"sv,
    "endsequence"sv,
    "endtable"sv,
    "endtask"sv,
    "enum"sv,
    "event"sv,
    "eventually"sv,
    "expect"sv,
    "export"sv,
    "extends"sv,
    "extern"sv,
    "final"sv,
    "first_match"sv,
    "for"sv,
    "force"sv,
    "foreach"sv,
    "forever"sv,
    "fork"sv,
    "forkjoin"sv,
    "function"sv,
    "generate"sv,
    "genvar"sv,
    "global"sv,
    "highz0"sv,
    "highz1"sv,
    "if"sv,
    "iff"sv,
    "ifnone"sv,
    "ignore_bins"sv,
    "illegal_bins"sv,
    "implements"sv,
    "implies"sv,
    "import"sv,
    "incdir"sv,
    "include"sv,
    "initial"sv,
    "inout"sv,
    "input"sv,
    "inside"sv,
    "instance"sv,
    "int"sv,
    "integer"sv,
    "interconnect"sv,
    "interface"sv,
    "intersect"sv,
    "join"sv,
    "join_any"sv,
    "join_none"sv,
    "large"sv,
    "let"sv,
    "liblist"sv,
    "library"sv,
    "local"sv,
    "localparam"sv,
    "logic"sv,
    "longint"sv,
    "macromodule"sv,
    "matches"sv,
    "medium"sv,
    "modport"sv,
    "module"sv,
    "nand"sv,
    "negedge"sv,
    "nettype"sv,
    "new"sv,
    "nexttime"sv,
    "nmos"sv,
    "nor"sv,
    "noshowcancelled"sv,
    "not"sv,
    "notif0"sv,
    "notif1"sv,
    "null"sv,
    "or"sv,
    "output"sv,
    "package"sv,
    "packed"sv,
    "parameter"sv,
    "pmos"sv,
    "posedge"sv,
    "primitive"sv,
    "priority"sv,
    "program"sv,
    "property"sv,
    "protected"sv,
    "pull0"sv,
    "pull1"sv,
    "pulldown"sv,
    "pullup"sv,
    "pulsestyle_ondetect"sv,
    "pulsestyle_onevent"sv,
    "pure"sv,
    "rand"sv,
    "randc"sv,
    "randcase"sv,
    "randsequence"sv,
    "rcmos"sv,
    "real"sv,
    "realtime"sv,
    "ref"sv,
    "reg"sv,
    "reject_on"sv,
    "release"sv,
    "repeat"sv,
    "restrict"sv,
    "return"sv,
    "rnmos"sv,
    "rpmos"sv,
    "rtran"sv,
    "rtranif0"sv,
    "rtranif1"sv,
    "s_always"sv,
    "s_eventually"sv,
    "s_nexttime"sv,
    "s_until"sv,
    "s_until_with"sv,
    "scalared"sv,
    "sequence"sv,
    "shortint"sv,
    "shortreal"sv,
    "showcancelled"sv,
    "signed"sv,
    "small"sv,
    "soft"sv,
    "solve"sv,
    "specify"sv,
    "specparam"sv,
    "static"sv,
    "string"sv,
    "strong"sv,
    "strong0"sv,
    "strong1"sv,
    "struct"sv,
    "super"sv,
    "supply0"sv,
    "supply1"sv,
    "sync_accept_on"sv,
    "sync_reject_on"sv,
    "table"sv,
    "tagged"sv,
    "task"sv,
    "this"sv,
    "throughout"sv,
    "time"sv,
    "timeprecision"sv,
    "timeunit"sv,
    "tran"sv,
    "tranif0"sv,
    "tranif1"sv,
    "tri"sv,
    "tri0"sv,
    "tri1"sv,
    "triand"sv,
    "trior"sv,
    "trireg"sv,
    "type"sv,
    "typedef"sv,
    "union"sv,
    "unique"sv,
    "unique0"sv,
    "unsigned"sv,
    "until"sv,
    "until_with"sv,
    "untyped"sv,
    "use"sv,
    "uwire"sv,
    "var"sv,
    "vectored"sv,
    "virtual"sv,
    "void"sv,
    "wait"sv,
    "wait_order"sv,
    "wand"sv,
    "weak"sv,
    "weak0"sv,
    "weak1"sv,
    "while"sv,
    "wildcard"sv,
    "wire"sv,
    "with"sv,
    "within"sv,
    "wor"sv,
    "xnor"sv,
    "xor"sv,
};

template <class List>
bool in(const List& list, std::string_view id) {
  return std::find(list.begin(), list.end(), id) != list.end();
}

}  // namespace

const char* reserved_reason(Language lang, std::string_view id) {
  switch (lang) {
    case Language::kC:
      if (in(kCKeywords, id))
        return "a C keyword";
      if (in(kCMacros, id) || in(kLowerCaseMacros, id))
        return "a macro of the C standard headers";
      if (reserved_c_prefix(id))
        return "reserved by the C standard library (a reserved prefix)";
      return nullptr;
    case Language::kCpp:
      if (in(kCppKeywords, id))
        return "a C++ keyword";
      if (in(kLowerCaseMacros, id) || in(kCMacros, id))
        return "a macro of the C/C++ standard headers or the compilers";
      if (id.find("__") != std::string_view::npos || id.starts_with("_"))
        return "reserved in C++ (a double underscore or a leading underscore)";
      return nullptr;
    case Language::kRdl:
      if (in(kRdlKeywords, id))
        return "a SystemRDL keyword";
      if (in(kSvKeywords, id))
        return "a SystemVerilog keyword (PeakRDL exports the SystemRDL to SystemVerilog)";
      return nullptr;
  }
  return nullptr;
}

}  // namespace odoloc::regmap
