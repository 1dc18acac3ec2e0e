# gapchain-continue's figure. Regenerate: gnuplot branch.gp (in the output folder).
# Stable orbits solid, unstable dashed, special points marked; with OVERLAY a brute-force
# diagram's summary.csv (gapchain-bifurcation) is drawn underneath in grey.
set terminal pngcairo size 1200,900 font 'sans,11'
set output 'branch.png'
set datafile separator ','
set multiplot layout 2,1 title '@TITLE@'
set grid
set key outside right
set xlabel '@PARAM@'
set ylabel 'F_m (reduced)'
overlay = '@OVERLAY@'
has_overlay = overlay ne ''
# Without an overlay this first plot draws nothing (every point undefined) and has no key entry.
plot (has_overlay ? overlay : 'branch.csv') every ::1 using 1:(has_overlay ? $3 : 1/0) with points pt 7 ps 0.2 lc rgb '#bbbbbb' title (has_overlay ? 'brute force (gapchain-bifurcation)' : ''), \
     'branch.csv' every ::1 using 1:($6 == 1 ? $3 : 1/0) with points pt 7 ps 0.35 lc rgb '#1f4e9c' title 'stable orbit', \
     'branch.csv' every ::1 using 1:($6 == 0 ? $3 : 1/0) with points pt 6 ps 0.35 lc rgb '#d62728' title 'unstable orbit', \
     'special.csv' every ::1 using 2:(strcol(1) eq 'fold' ? $4 : 1/0) with points pt 9 ps 1.6 lc rgb 'black' title 'fold', \
     'special.csv' every ::1 using 2:(strcol(1) eq 'period_doubling' ? $4 : 1/0) with points pt 5 ps 1.4 lc rgb '#2ca02c' title 'period doubling', \
     'special.csv' every ::1 using 2:(strcol(1) eq 'neimark_sacker' ? $4 : 1/0) with points pt 13 ps 1.6 lc rgb '#9467bd' title 'Neimark-Sacker', \
     'special.csv' every ::1 using 2:(strcol(1) eq 'grazing' ? $4 : 1/0) with points pt 3 ps 1.4 lc rgb '#ff7f0e' title 'grazing', \
     'special.csv' every ::1 using 2:(strcol(1) eq 'branch_point' ? $4 : 1/0) with points pt 11 ps 1.6 lc rgb '#8c564b' title 'branch point'
set ylabel 'largest |Floquet multiplier|'
set logscale y
plot 'branch.csv' every ::1 using 1:7 with points pt 7 ps 0.35 lc rgb '#1f4e9c' title '|mu|max', \
     1 with lines dt 2 lc rgb 'black' title '|mu| = 1'
unset multiplot
