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
        set terminal pngcairo size fig_width * fig_dpi, fig_height * fig_dpi enhanced font "sans,".fig_font \
            fontscale png_scale linewidth png_scale pointscale png_scale
    }
}
set output fig_out
set key samplen 2.5 spacing 1
