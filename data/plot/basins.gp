# gapchain-attractors' basin slice. Regenerate: gnuplot basins.gp (in the output folder).
# One colour per attractor id (attractors.csv); white: the run failed.
set terminal pngcairo size 900,800 font 'sans,11'
set output 'basins.png'
set datafile separator ','
set title '@TITLE@'
set xlabel '@XLABEL@ (reduced)'
set ylabel '@YLABEL@ (reduced)'
count = @COUNT@
set palette maxcolors (count > 0 ? count : 1)
set palette defined (0 '#1f77b4', 1 '#d62728', 2 '#2ca02c', 3 '#ff7f0e', 4 '#9467bd', 5 '#8c564b', 6 '#e377c2', 7 '#7f7f7f', 8 '#bcbd22', 9 '#17becf')
set cbrange [-0.5:(count > 0 ? count : 1) - 0.5]
set cbtics 1
set cblabel 'attractor id'
set autoscale fix
plot 'basins.csv' every ::1 using 1:2:($3 >= 0 ? $3 : 1/0) with image notitle
