# gapchain-bifurcation's figure. Regenerate: gnuplot bifurcation.gp (in the output folder).
set terminal pngcairo size 1200,900 font 'sans,11'
set output 'bifurcation.png'
set datafile separator ','
set multiplot layout 2,1 title '@TITLE@'
set ylabel '@VARIABLE@ (stroboscopic section)'
set grid
set key outside right
plot 'points.csv' every ::1 using (strcol(2) eq 'up' ? $1 : 1/0):3 with dots lc rgb '#1f4e9c' title '@UP_TITLE@', \
     'points.csv' every ::1 using (strcol(2) eq 'down' ? $1 : 1/0):3 with dots lc rgb '#d62728' title '@DOWN_TITLE@'
set ylabel 'F_m (reduced)'
set xlabel '@PARAM@'
plot 'summary.csv' every ::1 using (strcol(2) eq 'up' ? $1 : 1/0):3 with linespoints pt 7 ps 0.3 lc rgb '#1f4e9c' title '@UP_TITLE@', \
     'summary.csv' every ::1 using (strcol(2) eq 'down' ? $1 : 1/0):3 with linespoints pt 7 ps 0.3 lc rgb '#d62728' title '@DOWN_TITLE@'
unset multiplot
