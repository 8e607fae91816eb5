#include "bench/plot.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace nrsfm {
namespace bench {

std::string WritePlot(const BenchConfig& config, const PlotSpec& spec) {
  if (!config.plots) return "";
  static int gnuplot_state = -1;  // -1 unknown, 0 missing, 1 present
  if (gnuplot_state < 0) {
    gnuplot_state =
        std::system("command -v gnuplot > /dev/null 2>&1") == 0 ? 1 : 0;
    if (gnuplot_state == 0) {
      std::fprintf(stderr,
                   "note: gnuplot not found; plots skipped "
                   "(apt-get install gnuplot-nox)\n");
    }
  }
  if (gnuplot_state == 0) return "";
  namespace fs = std::filesystem;
  const fs::path dir(config.output_dir);
  const std::string data = (dir / (spec.name + ".dat")).string();
  const std::string script = (dir / (spec.name + ".gp")).string();
  const std::string image = (dir / (spec.name + ".svg")).string();
  {
    std::ofstream out(data);
    for (size_t s = 0; s < spec.series.size(); ++s) {
      out << "# " << spec.series[s].title << "\n";
      for (size_t i = 0; i < spec.series[s].x.size(); ++i) {
        out << spec.series[s].x[i] << " " << spec.series[s].y[i] << "\n";
      }
      out << "\n\n";
    }
  }
  {
    std::ofstream out(script);
    out << "set terminal svg size 720,480 dynamic enhanced font 'sans,12'\n"
        << "set output '" << image << "'\n"
        << "set title '" << spec.title << "' noenhanced\n"
        << "set xlabel '" << spec.xlabel << "' noenhanced\n"
        << "set ylabel '" << spec.ylabel << "' noenhanced\n"
        << "set grid\nset key top right noenhanced\n";
    if (spec.logx) out << "set logscale x\n";
    if (spec.logy) out << "set logscale y\n";
    out << "plot ";
    for (size_t s = 0; s < spec.series.size(); ++s) {
      out << (s == 0 ? "" : ", ") << "'" << data << "' index " << s
          << " using 1:2 with linespoints title '" << spec.series[s].title
          << "'";
    }
    out << "\n";
  }
  const std::string command = "gnuplot '" + script + "' > /dev/null 2>&1";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "note: gnuplot failed on %s; plot skipped\n",
                 script.c_str());
    return "";
  }
  return image;
}

}  // namespace bench
}  // namespace nrsfm
