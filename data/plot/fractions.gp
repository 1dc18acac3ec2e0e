# gapchain-attractors' basin fractions along a parameter. Regenerate: gnuplot fractions.gp (in
# the output folder). Top: the fractions stacked, one colour per attractor label (labels 0-9
# distinct colours, as in basins.gp; from 10 on the colours repeat, hatched); bottom: the F_m of
# each attractor where it exists (from label 10 on, open symbols).
set terminal pngcairo size 1100,900 font 'sans,11'
set output 'fractions.png'
set datafile separator ','
count = @COUNT@
array R[10] = [31, 214, 44, 255, 148, 140, 227, 127, 188, 23]
array G[10] = [119, 39, 160, 127, 103, 86, 119, 127, 189, 190]
array B[10] = [180, 40, 44, 14, 189, 75, 194, 127, 34, 207]
colour(i) = sprintf('#%02x%02x%02x', R[i % 10 + 1], G[i % 10 + 1], B[i % 10 + 1])
set multiplot layout 2,1 title '@TITLE@'
set key outside right
set grid
set autoscale xfix
set xlabel '@PARAM@'
set ylabel 'basin fraction (stacked)'
set yrange [0:1]
frac(k) = column(2 + 5 * k)
below(i) = (i == 0 ? 0 : sum [k=0:i-1] frac(k))
solid = count < 10 ? count : 10
plot for [i=0:solid-1] 'fractions.csv' every ::1 using 1:(below(i)):(below(i) + frac(i)) with filledcurves fs solid 0.7 lc rgb colour(i) title sprintf('attractor %d', i), \
     for [i=10:count-1] 'fractions.csv' every ::1 using 1:(below(i)):(below(i) + frac(i)) with filledcurves fs pattern 1 + (i / 10 - 1) % 7 lc rgb colour(i) title sprintf('attractor %d', i)
set ylabel 'F_m (reduced)'
set autoscale y
plot for [i=0:count-1] 'fractions.csv' every ::1 using 1:(frac(i) > 0 ? column(4 + 5 * i) : 1/0) with linespoints pt (i < 10 ? 7 : 6 + 2 * ((i / 10 - 1) % 3)) ps 0.6 lc rgb colour(i) title sprintf('attractor %d', i)
unset multiplot
