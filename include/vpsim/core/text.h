#pragma once
/// @file
/// Text helpers for messages and strict number parsing. Every message that quotes user text goes
/// through quoteUser()/escaped(), so an error line never carries raw newlines, terminal escapes,
/// invalid UTF-8 or a 10 MB string.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace vpsim {

/// Longest piece of user text quoted in a message before it is cut with "...".
constexpr size_t MESSAGE_QUOTE_LIMIT = 80;

/// `text` with control characters, DEL and bytes that are not valid UTF-8 written as \n, \t,
/// \xNN; cut after `limit` characters (counting each escape as its characters) with "...".
std::string escaped(std::string_view text, size_t limit = MESSAGE_QUOTE_LIMIT);
/// escaped(text) in single quotes: the form for quoting user text in messages.
std::string quoteUser(std::string_view text, size_t limit = MESSAGE_QUOTE_LIMIT);

/// Length of the decimal number at the start of `text` (optional sign, digits with an optional
/// point, optional exponent), 0 when there is none. Hexadecimal, "inf" and "nan", which strtod
/// would accept, are not numbers here.
size_t decimalPrefixLength(std::string_view text);
/// The whole of `text` as a decimal number (no surrounding space), or nullopt when it is not
/// one. A finite-range check is the caller's: 1e400 comes back as +inf.
std::optional<double> parseDecimal(std::string_view text);

/// Text for HTML element content or a quoted attribute: & < > " ' as entities, control bytes and
/// invalid UTF-8 as U+FFFD. Everything the HTML report quotes (job name, file names) goes through
/// it.
std::string htmlEscape(std::string_view text);

/// ASCII lower case.
std::string asciiLower(std::string_view text);

/// `value` with `significantDigits` significant digits in the shortest form ("%g" style, the C
/// locale), for messages and files: 0.1, 1e+07, 2.5.
std::string formatNumber(double value, int significantDigits = 6);
/// `value` for people: ~`significantDigits` significant digits without trailing zeros and
/// without an exponent from 1e-4 to 1e15 ("78", "0.35", "12346"), then " " and `unit` when one
/// is given: "78 mJ/cm^2", "1 mm". The form for every number in a message, log line or report
/// text; counts stay integers (std::to_string).
std::string formatQuantity(double value, std::string_view unit = "", int significantDigits = 4);

}  // namespace vpsim
