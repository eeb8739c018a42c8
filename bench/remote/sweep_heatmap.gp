# Heat maps of haptic_link_sweep's tables: run inside the folder holding pinch_haptic.csv,
# pinch_global.csv, rub_haptic.csv and rub_global.csv (`gnuplot PATH/sweep_heatmap.gp`); writes
# remote_heatmap.png there. Columns: 2 rtt_ms, 3 loss, 5 peak_N, 10 error_rms_N; the first data row
# is the no-delay run, the reference of both figures (point 0 once columnhead takes the header line).
set datafile separator ','
set key autotitle columnhead
set terminal pngcairo size 1100,1500 font ',9'
set output 'remote_heatmap.png'
rtt_index(x) = x == 0 ? 0 : x == 10 ? 1 : x == 20 ? 2 : x == 50 ? 3 : x == 100 ? 4 : 5
loss_index(p) = p == 0 ? 0 : p <= 0.01 ? 1 : p <= 0.05 ? 2 : 3
set xtics ('0' 0, '10' 1, '20' 2, '50' 3, '100' 4, '200' 5)
set ytics ('0' 0, '1' 1, '5' 2, '10' 3)
set xlabel 'round trip [ms]'
set ylabel 'loss each way [%]'
set xrange [-0.5:5.5]
set yrange [-0.5:3.5]
set palette defined (0 '#1a9850', 0.5 '#fee08b', 1 '#d73027')
set multiplot layout 4,2
do for [file in 'pinch_haptic.csv pinch_global.csv rub_haptic.csv rub_global.csv'] {
  stats [*:*][*:*] file using 5 every ::0::0 nooutput name 'ref'
  panel = (strstrt(file, 'pinch') ? 'pinch, ' : 'rub, ') . (strstrt(file, 'haptic') ? 'simulation far' : 'global_sim far')
  set cbrange [0:50]
  set cblabel 'force error RMS [% of no-delay peak]'
  set title panel . ': force error' . (strstrt(file, 'haptic') ? ' (200 ms: refused, no force)' : '') noenhanced
  plot file using (rtt_index($2)):(loss_index($3)):(0.5):(0.5):(100 * $10 / ref_max) with boxxyerror fs solid \
       lc palette notitle, \
       '' using (rtt_index($2)):(loss_index($3)):(sprintf('%.0f', 100 * $10 / ref_max)) with labels notitle
  set cbrange [80:200]
  set cblabel 'peak force [% of no-delay peak]'
  set title panel . ': peak force' noenhanced
  plot file using (rtt_index($2)):(loss_index($3)):(0.5):(0.5):(100 * $5 / ref_max) with boxxyerror fs solid \
       lc palette notitle, \
       '' using (rtt_index($2)):(loss_index($3)):(sprintf('%.0f', 100 * $5 / ref_max)) with labels notitle
}
unset multiplot
