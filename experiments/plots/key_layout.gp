# key_layout.gp: the key below the axes of the curve figures, in as many columns as the longest
# label lets fit the width (at most 4), loaded before terminal.gp with
#   n_keys      the number of curves
#   key_maxlen  the longest label's length (characters)
#   fig_width   the figure's width in inches (fig_font: its text size, default 9)
# Sets key_rows and fig_height (4 in of axes and labels, and the key's rows below them); after
# terminal.gp, `@key_below font @font_key` sets the key (its text 1 pt below fig_font, 2 pt for labels
# longer than 30 characters). gnuplot sizes a key's columns by a character width
# larger than the average of a proportional font: `width` takes part of the surplus back.

if (!exists("fig_font")) { fig_font = 9 }
key_font = (key_maxlen > 30 ? fig_font - 2 : fig_font - 1)
key_char = 0.55 * key_font / 72.0            # average character width [in]
key_sample = 4 * key_char + 0.35             # sample line, marker and gaps [in]
key_cols = int(fig_width / (key_maxlen * key_char + key_sample))
key_cols = (key_cols < 1 ? 1 : (key_cols > 4 ? 4 : key_cols))
key_rows = int((n_keys + key_cols - 1) / key_cols)
fig_height = 4.0 + 0.17 * key_rows * key_font / 8.0
key_below = sprintf("set key below center vertical maxrows %d width %d noenhanced height 1.5 reverse Left", key_rows, -int(0.2 * key_maxlen))
