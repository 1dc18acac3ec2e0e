# Histograms of F_m from one or more gapchain-sweep CSVs, with reference values as vertical lines.
# Usage: gnuplot -e "csvs='a.csv b.csv'; labels='A B'; refs='0.52 5.85'; reflabels='measured harmonic';
#                    binwidth=0.05; xmin=0.4; xmax=2 (optional); png='out.png'; title='...'" docs/plot/fm-histogram.gp
# (labels and reflabels are space-separated words; use _ for spaces, shown as spaces)
set terminal pngcairo size 1000,600 font 'sans,11'
set output png
set datafile separator ','
set datafile columnheaders
set grid
set key at graph 0.98, graph 0.88 right top noenhanced
set xlabel 'F_m (reduced)'
set ylabel 'points per bin'
set title title noenhanced
set style fill transparent solid 0.45 border
if (exists('xmin')) set xrange [xmin:xmax]
bin(v) = binwidth * (floor(v / binwidth) + 0.5)
unspace(s) = system("echo '" . s . "' | tr _ ' '")
set for [k = 1:words(refs)] arrow from word(refs, k) + 0, graph 0 to word(refs, k) + 0, graph 1 nohead lw 2 dt 2 lc k + 3
set for [k = 1:words(refs)] label unspace(word(reflabels, k)) at word(refs, k) + 0, graph 0.95 left offset 0.5, 0 noenhanced
set boxwidth binwidth
plot for [k = 1:words(csvs)] word(csvs, k) using (bin(column('F_m'))):(1) smooth frequency with boxes lc k title unspace(word(labels, k))
