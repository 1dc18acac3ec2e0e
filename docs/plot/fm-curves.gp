# F_m against one swept parameter, one curve per value of another, from a gapchain-sweep CSV.
# Usage: gnuplot -e "csv='r.csv'; png='out.png'; xcol='e_r'; groupcol='fc'; values='1 10 100 1000'; title='...'" docs/plot/fm-curves.gp
# (not "x": that name is gnuplot's dummy variable)
set terminal pngcairo size 1000,650 font 'sans,11'
set output png
set datafile separator ','
set datafile columnheaders
set grid
set key outside right title groupcol noenhanced
set xlabel xcol noenhanced
set ylabel 'F_m (reduced)'
set title title noenhanced
# gapchain-sweep writes rows as threads finish them; in file order, the rows of other curves
# (skipped as 1/0) would cut a curve into pieces, so the rows are read in index order.
rows = sprintf("< (head -n 1 '%s'; tail -n +2 '%s' | sort -t, -k1,1n)", csv, csv)
plot for [v in values] rows using (abs(column(groupcol) - v) < 1e-9 * (1 + v) ? column(xcol) : 1/0):(column('F_m')) \
     smooth unique with linespoints pt 7 ps 0.6 lw 1.5 title v
