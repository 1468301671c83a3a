// Rendering figures with gnuplot: one script per figure kind in experiments/plots/, run as
//   gnuplot -e "lgvi_format = 'png'" -c SCRIPT OUT TITLE XLABEL YLABEL in1.csv label1 [...]
// The format (PNG, PDF or SVG) is the output file's extension's; the scripts' shared terminal
// (experiments/plots/terminal.gp) draws it at the figure's size in inches.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "experiments/output/palette.hpp"

namespace lgvi::experiments {

class TempPath;

/// The gnuplot scripts compiled in: <source>/experiments/plots.
std::filesystem::path default_plots_dir();
/// The gnuplot executable found at configure time.
std::string default_gnuplot();

/// `path` as gnuplot must be given it (file names only, never inside a command): gnuplot runs a
/// data file, output or loaded file whose name starts with '<' or '|' as a shell command and
/// reads "-", "+", "++", "$name" and "" as special files; an absolute path, or a relative one
/// prefixed with "./", is always a plain file.
std::string gnuplot_path(const std::filesystem::path& path);

/// `text` as a gnuplot single-quoted string literal, for the files the scripts `load`: no escape
/// sequences and no backquote (shell) substitution happen inside single quotes; ' is doubled.
/// Control characters (newline, tab, ...) cannot appear inside one: they become spaces.
std::string gnuplot_literal(const std::string& text);

/// gnuplot_literal(gnuplot_path(path)); throws OutputError for a path with a control character
/// (it could not be represented: a changed name would read another file).
std::string gnuplot_path_literal(const std::filesystem::path& path);

/// A figure's file format: gnuplot's pngcairo, pdfcairo or svg terminal.
enum class FigureFormat { Png, Pdf, Svg };

/// "png", "pdf", "svg".
const char* figure_format_name(FigureFormat format);
/// The format named "png", "pdf" or "svg"; nullopt for any other text.
std::optional<FigureFormat> figure_format_named(std::string_view name);
/// The formats of a comma-separated list ("png", "png,pdf"): each named once, in the list's
/// order. Throws InvalidInput naming `option` ("--format") and the word that is not a format, a
/// repeated one or an empty list.
std::vector<FigureFormat> figure_formats_named(const std::string& option, std::string_view list);
/// The file name extension with its dot: ".png", ".pdf", ".svg".
std::string figure_extension(FigureFormat format);
/// The format of a figure file by its extension: .pdf, .svg; PNG for any other.
FigureFormat figure_format_of(const std::filesystem::path& file);

/// `text` broken at spaces into lines of at most `width` characters (a longer word keeps a line
/// of its own): figure titles that fit the figure's width.
std::string wrap_text(const std::string& text, std::size_t width);

/// True if `file` is a whole PNG: the signature first and the IEND chunk last (a full disk lets
/// gnuplot exit 0 with a truncated file).
bool is_complete_png(const std::filesystem::path& file);
/// True if `file` is a whole PDF: "%PDF-" first and the end-of-file marker "%%EOF" last (line
/// ends after it allowed).
bool is_complete_pdf(const std::filesystem::path& file);
/// True if `file` is a whole SVG: an XML declaration or "<svg" first (leading blanks allowed) and
/// the closing "</svg>" last (blanks after it allowed).
bool is_complete_svg(const std::filesystem::path& file);
/// The completeness check of `format`.
bool is_complete_figure(const std::filesystem::path& file, FigureFormat format);

/// One curve: a CSV written by lgvi-testbed, its legend entry and its style (palette.hpp; none:
/// the style of the label, plot_style(label)).
struct Curve {
  std::filesystem::path csv;
  std::string label;
  std::optional<PlotStyle> style = std::nullopt;
};

/// Runs `gnuplot -c script OUT title xlabel ylabel csv1 label1 ...` with OUT a temporary next to
/// `png`, renamed onto `png` when gnuplot exited 0 and wrote a complete figure in the format of
/// `png`'s extension (figure_format_of, is_complete_figure). Paths are handed over as
/// gnuplot_path(). gnuplot's stdout
/// is discarded; its stderr is kept for the error message. Throws OutputError (first line of
/// gnuplot's stderr) on failure, leaving no file; Interrupted (interrupt.hpp) on SIGINT/SIGTERM.
void render_plot(const std::string& gnuplot, const std::filesystem::path& script,
                 const std::filesystem::path& png, const std::string& title, const std::string& xlabel,
                 const std::string& ylabel, const std::vector<Curve>& curves);

/// Runs `gnuplot -e "lgvi_format = 'FORMAT'" -c script OUT args...` the same way (OUT a
/// temporary renamed onto `png`; FORMAT png, pdf or svg by `png`'s extension, which the scripts'
/// terminal.gp draws). Paths among `args` must come from gnuplot_path() (the scripts read them as
/// file names).
/// gnuplot -c passes at most 9 arguments: scripts with many curves take a curve-list file.
/// The temporaries the script reads (a curve list, a data file: `inputs`) are named in `args`
/// (and in each other) by their TempPath::fd_path(); their descriptors are inherited by gnuplot,
/// which so reads the files this process wrote whatever happens to their names meanwhile. The
/// figure's temporary and gnuplot's log are handed over the same way: no file gnuplot opens can
/// be swapped for a symlink by someone who can write in the output directory.
/// SIGINT/SIGTERM (interrupt.hpp) while gnuplot runs: gnuplot is ended and reaped, nothing is
/// published, and Interrupted is thrown. Throws OutputError.
void run_gnuplot_script(const std::string& gnuplot, const std::filesystem::path& script,
                        const std::filesystem::path& png, const std::vector<std::string>& args,
                        const std::vector<const TempPath*>& inputs = {});

}  // namespace lgvi::experiments
