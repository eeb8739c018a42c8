# The dual layer's speed/accuracy trade from dual_layer_sweep's CSV:
#   gnuplot -e "csv='dual_layer_sweep.csv'; png='dual_layer_sweep.png'" bench/dual_layer/plot_sweep.gp
set terminal pngcairo size 1100,650 font ",10"
set output png
set datafile separator ","
set key outside right
set logscale x
set xlabel "cost: microseconds per local tick"
set ylabel "force error, % of the reference's peak"
set title "dual layer vs the single-layer reference (points of one line: local 1, 2, 5 kHz)"
# c: mesh mm then refinement levels, one digit each
plot for [m in "2 5 10 15"] for [c in "20 40 41"] \
  csv using ($2==m+0 && $3==c[1:1]+0 && $9==c[2:2]+0 ? $4 : 1/0):7 \
  with linespoints title sprintf("margin %s mm, mesh %s mm, refined %s", m, c[1:1], c[2:2])
