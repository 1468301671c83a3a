# slsqp_panel.gp: panel (c) of the direct-method figures (fig_cart_pendulum.gp,
# fig_connected_bodies.gp), loaded by them with
#   history     the ocp-SYSTEM-history.csv file (columns start, iteration, violation, cost)
#   best_start  the start whose solution the figure shows (the summary's best_start), or -1
#   starts      the number of starts (the summary's starts), or 0 when not known
#   cost_unit   the cost's unit (enhanced text)
# A multistart run writes every start's history one after the other: the panel draws the shown
# start's evaluations alone (its terminal violation on the left axis, its cost on the right),
# so the convergence that produced the solution is readable; with best_start -1, every start's
# evaluations in file order.

if (best_start >= 0) {
    panel_x(s, i, e) = (s == best_start ? i : NaN)
    set title sprintf("(c) SLSQP (start %d/%d)", best_start + 1, starts)
    set xlabel "evaluation (this start)"
} else {
    panel_x(s, i, e) = e
    set title "(c) SLSQP"
    set xlabel "evaluation"
}
stats history using (panel_x(column("start"), column("iteration"), column("evaluation"))) nooutput
set xtics 0, iteration_step(STATS_max); set mxtics default; set format x "%g"
set ylabel "violation"
set logscale y
set format y "10^{%L}"
set ytics 1e4 nomirror
set logscale y2
set format y2 "10^{%L}"
set y2tics 100 font @font_6 offset -0.5, 0
set label 101 "violation (left)" at graph 0.5, graph 1 offset 0, row_2 center textcolor rgb c2 font @font_6
set label 102 "cost [".cost_unit."] (right)" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
plot history using (panel_x(column("start"), column("iteration"), column("evaluation"))):(positive(column("violation"))) \
         with lines lw 0.8 lc rgb c2, \
     history using (panel_x(column("start"), column("iteration"), column("evaluation"))):(positive(column("cost"))) \
         axes x1y2 with lines lw 0.8 lc rgb c1
unset label
unset logscale y
unset logscale y2
unset y2tics
set ytics autofreq mirror
set format y "%g"
