# gapchain-attractors' basin slice. Regenerate: gnuplot basins.gp (in the output folder).
# One colour per attractor id (attractors.csv, ids 0-9 distinct, then repeating); white: the run
# failed.
set terminal pngcairo size 900,800 font 'sans,11'
set output 'basins.png'
set datafile separator ','
set title '@TITLE@ (@COUNT@ attractors)'
set xlabel '@XLABEL@ (reduced)'
set ylabel '@YLABEL@ (reduced)'
array R[10] = [31, 214, 44, 255, 148, 140, 227, 127, 188, 23]
array G[10] = [119, 39, 160, 127, 103, 86, 119, 127, 189, 190]
array B[10] = [180, 40, 44, 14, 189, 75, 194, 127, 34, 207]
red(id) = id < 0 ? 255 : R[int(id) % 10 + 1]
green(id) = id < 0 ? 255 : G[int(id) % 10 + 1]
blue(id) = id < 0 ? 255 : B[int(id) % 10 + 1]
set autoscale fix
set key outside right
plot 'basins.csv' every ::1 using 1:2:(red($3)):(green($3)):(blue($3)) with rgbimage notitle, \
     for [i=0:(@COUNT@ < 10 ? @COUNT@ : 10) - 1] NaN with boxes fs solid lc rgb sprintf('#%02x%02x%02x', R[i+1], G[i+1], B[i+1]) title sprintf('attractor %d', i)
