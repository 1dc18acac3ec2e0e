# gapchain-classify --map's figures. Regenerate: gnuplot map.gp (in the output folder).
set terminal pngcairo size 1000,750 font 'sans,11'
set datafile separator ','
set xlabel 'f_r'
set ylabel 'e_r'
set xrange [@F_FROM@:@F_TO@]
set yrange [@E_FROM@:@E_TO@]
set key top right opaque
eps = @EPS@
no_impact(x) = 1/sqrt((1-x**2)**2+4*eps**2*x**2)
set output 'regimes.png'
set title 'Regimes, @TITLE@'
set palette maxcolors 4
set palette defined (0 '#e8e8e8', 1 '#4c9be8', 2 '#f2b134', 3 '#d62728')
set cbrange [-0.5:3.5]
set cbtics ('no contact' 0, 'periodic' 1, 'quasi-periodic' 2, 'chaotic' 3)
set rmargin 16
plot 'map.csv' every ::1 using 2:1:4 @STYLE@ notitle, no_impact(x) with lines lw 2 lc rgb 'black' title 'eq (20): no impact above'
set output 'force.png'
set title 'F_m, @TITLE@'
set palette maxcolors 0
set palette rgbformulae 21,22,23
set cbrange [*:*]
set cbtics auto
set rmargin -1
set cblabel 'F_m'
# The no-contact corner is black here: a white key on it shows the white boundary's sample.
set key noopaque textcolor rgb 'white'
plot 'map.csv' every ::1 using 2:1:6 @STYLE@ notitle, no_impact(x) with lines lw 2 lc rgb 'white' title 'eq (20): no impact above'
