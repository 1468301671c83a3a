# terminal.gp: the output terminal of every figure script, loaded by them from their own
# directory (plots_dir, the directory part of the script's path ARG0).
#
# The script sets, before loading it:
#   fig_out                the output file (its ARG1: a loaded file does not see the caller's ARGn)
#   fig_width, fig_height  the figure's size in inches (a PDF or SVG is that size; a PNG fig_dpi
#                          pixels per inch, its text, lines and markers scaled alike)
#   fig_font               the text size in points (optional; default 9)
#   fig_dpi                the PNG's pixels per inch (optional; default 144)
# The format: lgvi_format, "png", "pdf" or "svg" (lgvi-testbed passes it with -e, because it
# writes the figure through a temporary name); otherwise OUT's extension (.pdf, .svg; anything
# else: PNG). Sets the terminal, the output (fig_out) and the key's sample length and spacing.

if (!exists("fig_font")) { fig_font = 9 }
if (!exists("fig_dpi")) { fig_dpi = 144 }
png_scale = fig_dpi / 72.0
if (!exists("lgvi_format")) {
    lgvi_format = "png"
    n_out = strlen(fig_out)
    if (n_out > 4 && fig_out[n_out-3:n_out] eq ".pdf") { lgvi_format = "pdf" }
    if (n_out > 4 && fig_out[n_out-3:n_out] eq ".svg") { lgvi_format = "svg" }
}
if (lgvi_format eq "pdf") {
    set terminal pdfcairo size fig_width, fig_height enhanced font "sans,".fig_font linewidth 1
} else {
    if (lgvi_format eq "svg") {
        set terminal svg size fig_width * 72, fig_height * 72 dynamic enhanced font "sans,".fig_font linewidth 1
    } else {
        # The text size scaled in the font itself: gnuplot lays keys out by the font's nominal
        # size, and with `fontscale` it would reserve twice the room a key needs.
        set terminal pngcairo size fig_width * fig_dpi, fig_height * fig_dpi enhanced \
            font "sans,".sprintf("%g", fig_font * png_scale) linewidth png_scale pointscale png_scale
    }
}
set output fig_out
# Smaller text (tick labels, curve names) as macros, `font @font_6`, scaled in a PNG as fig_font is.
font_6 = sprintf("\",%g\"", 6 * (lgvi_format eq "png" ? png_scale : 1))
if (exists("key_font")) { font_key = sprintf("\",%g\"", key_font * (lgvi_format eq "png" ? png_scale : 1)) }
set key samplen 2.5 spacing 1
