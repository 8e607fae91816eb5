set terminal svg size 720,480 dynamic enhanced font 'sans,12'
set output './bench_results/shoe_error.svg'
set title 'shoe: 3D error vs K (Table 1 style)' noenhanced
set xlabel 'K' noenhanced
set ylabel '% of shape size' noenhanced
set grid
set key top right noenhanced
plot './bench_results/shoe_error.dat' index 0 using 1:2 with linespoints title 'monocular 3D', './bench_results/shoe_error.dat' index 1 using 1:2 with linespoints title 'monocular z', './bench_results/shoe_error.dat' index 2 using 1:2 with linespoints title '2 cams + rigidity 3D'
