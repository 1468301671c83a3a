// The shortest decimal form of a double that reads back to the same double, written byte for
// byte as std::to_chars(first, last, x) writes it (no format argument: fixed or scientific,
// whichever is shorter, fixed on a tie), at a fraction of its cost: the CSV rows' numbers
// (csv_writer.cpp).
//
// The digits come from R. Giulietti's Schubfach algorithm ("The Schubfach way to render doubles",
// 2020, sections 9-10): one 64x128-bit product per bound against a table of 10^-k, rounded to
// odd, then a choice among at most four candidates. Zero, subnormals, infinities, NaN and
// |x| >= 2^52 (integers of 16 digits and more, left out of the fast path and of its proof
// obligations) go to std::to_chars itself. write_csv_numbers formats a whole row with the formatter inlined (no
// call a number).
#pragma once

#include <cstddef>
#include <span>

namespace lgvi::experiments {

/// Longest text write_shortest writes: "-2.2250738585072014e-308".
inline constexpr std::size_t kShortestMaxChars = 24;
/// Bytes write_shortest may write at `first`: the text, and past its end scratch bytes of its
/// fixed-length copies.
inline constexpr std::size_t kShortestRoom = 40;

/// Writes x at `first` (room for kShortestRoom bytes) as std::to_chars(first, last, x) does;
/// returns the end of the text.
char* write_shortest(char* first, double x);

/// One CSV row: the values by write_shortest, ',' between them, '\n' after (room for
/// values.size() (kShortestMaxChars + 1) + kShortestRoom bytes); returns the end of the row.
char* write_csv_numbers(char* first, std::span<const double> values);

}  // namespace lgvi::experiments
