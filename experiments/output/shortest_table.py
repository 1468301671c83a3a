#!/usr/bin/env python3
"""The table of powers of ten of write_shortest (shortest.cpp, Schubfach section 10).

For k = -324 .. 292: g(k) = floor(10^-k 2^(125 - floor(log2 10^-k))) + 1, so 2^125 < g <= 2^126,
stored as {g >> 63, g mod 2^63}; computed in exact rational arithmetic. Also checks the
multiply-and-shift logarithms of shortest.cpp against exact values.

  shortest_table.py            prints the table's rows as shortest.cpp holds them
  shortest_table.py --check F  exits 1 unless F (shortest.cpp) holds exactly these rows
"""
import re
import sys
from fractions import Fraction

K_MIN, K_MAX = -324, 292


def floor_log2(x: Fraction) -> int:
    """floor(log2 x) for a positive rational x, exactly."""
    e = x.numerator.bit_length() - x.denominator.bit_length()
    if Fraction(2) ** e > x:
        e -= 1
    elif Fraction(2) ** (e + 1) <= x:
        e += 1
    assert Fraction(2) ** e <= x < Fraction(2) ** (e + 1)
    return e


def g(k: int) -> int:
    p = Fraction(10) ** (-k)
    scaled = p * Fraction(2) ** (125 - floor_log2(p))
    value = scaled.numerator // scaled.denominator + 1
    assert 2**125 < value <= 2**126
    return value


def rows():
    for k in range(K_MIN, K_MAX + 1):
        v = g(k)
        yield f"    {{0x{v >> 63:016x}, 0x{v & ((1 << 63) - 1):016x}}},  // k = {k}"


def floor_log10(x: Fraction) -> int:
    e = 0
    while Fraction(10) ** e > x:
        e -= 1
    while Fraction(10) ** (e + 1) <= x:
        e += 1
    return e


def check_logarithms() -> list:
    """The shift formulas of shortest.cpp against exact values (q in [-1100, 1000], e in
    [-330, 330]); returns the mismatches."""
    bad = []
    for q in range(-1100, 1001):
        if (q * 78913) >> 18 != floor_log10(Fraction(2) ** q):
            bad.append(f"floor_log10_pow2({q})")
        if (q * 631305 - 261663) >> 21 != floor_log10(Fraction(3, 4) * Fraction(2) ** q):
            bad.append(f"floor_log10_three_quarters_pow2({q})")
    for e in range(-330, 331):
        if (e * 1741647) >> 19 != floor_log2(Fraction(10) ** e):
            bad.append(f"floor_log2_pow10({e})")
    return bad


def main() -> int:
    expected = list(rows())
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        text = open(sys.argv[2], encoding="utf-8").read()
        held = [line for line in text.splitlines() if re.match(r"\s*\{0x[0-9a-f]{16}, 0x[0-9a-f]{16}\},  // k = ", line)]
        if held != expected:
            mismatch = next((i for i, (a, b) in enumerate(zip(held, expected)) if a != b), min(len(held), len(expected)))
            print(f"{sys.argv[2]}: the table differs from the exact values at row {mismatch} "
                  f"({len(held)} rows, {len(expected)} expected)")
            return 1
        bad = check_logarithms()
        if bad:
            print("shift logarithms off the exact values: " + ", ".join(bad[:10]))
            return 1
        print(f"{len(expected)} rows equal the exact values; the shift logarithms are exact")
        return 0
    if len(sys.argv) != 1:
        print(__doc__)
        return 2
    print("\n".join(expected))
    return 0


if __name__ == "__main__":
    sys.exit(main())
