set terminal svg size 720,480 dynamic enhanced font 'sans,12'
set output './bench_results/scale_time.svg'
set title 'time vs F*P (K = 5, linear solver auto)' noenhanced
set xlabel 'F * P' noenhanced
set ylabel 'seconds' noenhanced
set grid
set key top right noenhanced
set logscale x
set logscale y
plot './bench_results/scale_time.dat' index 0 using 1:2 with linespoints title 's per LM iteration', './bench_results/scale_time.dat' index 1 using 1:2 with linespoints title 'total s'
