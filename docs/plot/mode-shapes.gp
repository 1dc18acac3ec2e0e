# Mode shapes of a linear chain from `gapchain-modes --csv`.
# Usage: gnuplot -e "csv='shapes.csv'; png='out.png'; title='...'" docs/plot/mode-shapes.gp
set terminal pngcairo size 1000,650 font 'sans,11'
set output png
set datafile separator ','
set xlabel 'body i'
set ylabel 'mode shape phi_k(i) (unit norm)'
set grid
set key outside right
set title title
set xrange [0.5:*]
stats csv using 1 nooutput
n = STATS_columns
plot for [c=2:n] csv using 1:c with linespoints pt 7 ps 0.8 lw 1.5 title columnheader(c), \
     for [c=2:2] csv using 1:(sin(pi*$1/(STATS_max+1))*sqrt(2.0/(STATS_max+1))) with lines dt 2 lc rgb 'gray40' title 'sin(pi i/(Nm+1)), normalised'
