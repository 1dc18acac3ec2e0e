# gapchain-attractors' basin fractions along a parameter. Regenerate: gnuplot fractions.gp (in
# the output folder). Top: the fractions stacked, one colour per attractor label; bottom: the
# F_m of each attractor where it exists.
set terminal pngcairo size 1100,900 font 'sans,11'
set output 'fractions.png'
set datafile separator ','
count = @COUNT@
set multiplot layout 2,1 title '@TITLE@'
set key outside right
set grid
set autoscale xfix
set xlabel '@PARAM@'
set ylabel 'basin fraction (stacked)'
set yrange [0:1]
frac(k) = column(2 + 4 * k)
below(i) = (i == 0 ? 0 : sum [k=0:i-1] frac(k))
plot for [i=0:count-1] 'fractions.csv' every ::1 using 1:(below(i)):(below(i) + frac(i)) with filledcurves fs solid 0.7 lc i+1 title sprintf('attractor %d', i)
set ylabel 'F_m (reduced)'
set autoscale y
plot for [i=0:count-1] 'fractions.csv' every ::1 using 1:(frac(i) > 0 ? column(4 + 4 * i) : 1/0) with linespoints pt 7 ps 0.6 lc i+1 title sprintf('attractor %d', i)
unset multiplot
