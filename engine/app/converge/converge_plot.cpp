// plot.svg: relMSE against cumulative render seconds on log-log axes, hand-written SVG (no dependencies).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "app/converge/converge_report.h"
#include "io/atomic_write.h"
#include "io/image.h"

namespace fh {
namespace {

constexpr double W = 760, H = 480, LEFT = 80, RIGHT = 220, TOP = 30, BOTTOM = 60;
const char* COLOURS[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                         "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else out += c;
    }
    return out;
}

// Maps log10 of data to pixels; the ranges are whole decades around the data.
struct Axis {
    double lo, hi, p0, p1;
    double to_pixel(double v) const { return p0 + (std::log10(v) - lo) / (hi - lo) * (p1 - p0); }
};

Axis make_axis(double vmin, double vmax, double p0, double p1) {
    double lo = std::floor(std::log10(vmin)), hi = std::ceil(std::log10(vmax));
    if (hi <= lo) hi = lo + 1;
    return {lo, hi, p0, p1};
}

}  // namespace

void write_plot_svg(const std::filesystem::path& file, const ConvergeReport& report) {
    double tmin = 1e300, tmax = 0, emin = 1e300, emax = 0;
    for (const ConvergeCurve& c : report.curves)
        for (const ConvergeStep& st : c.steps)
            if (st.seconds > 0 && st.errors.relmse > 0) {
                tmin = std::min(tmin, st.seconds), tmax = std::max(tmax, st.seconds);
                emin = std::min(emin, st.errors.relmse), emax = std::max(emax, st.errors.relmse);
            }
    if (tmax == 0) tmin = 1e-3, tmax = 1, emin = 1e-3, emax = 1;
    const Axis x = make_axis(tmin, tmax, LEFT, W - RIGHT), y = make_axis(emin, emax, H - BOTTOM, TOP);

    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 "
        << W << " " << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    // Decade grid lines and labels.
    for (double d = x.lo; d <= x.hi + 1e-9; d += 1) {
        const double px = x.to_pixel(std::pow(10.0, d));
        svg << "<line x1=\"" << num(px) << "\" y1=\"" << TOP << "\" x2=\"" << num(px) << "\" y2=\"" << H - BOTTOM
            << "\" stroke=\"#ddd\"/>\n<text x=\"" << num(px) << "\" y=\"" << H - BOTTOM + 18
            << "\" text-anchor=\"middle\">1e" << int(d) << "</text>\n";
    }
    for (double d = y.lo; d <= y.hi + 1e-9; d += 1) {
        const double py = y.to_pixel(std::pow(10.0, d));
        svg << "<line x1=\"" << LEFT << "\" y1=\"" << num(py) << "\" x2=\"" << W - RIGHT << "\" y2=\"" << num(py)
            << "\" stroke=\"#ddd\"/>\n<text x=\"" << LEFT - 8 << "\" y=\"" << num(py + 4)
            << "\" text-anchor=\"end\">1e" << int(d) << "</text>\n";
    }
    svg << "<rect x=\"" << LEFT << "\" y=\"" << TOP << "\" width=\"" << W - LEFT - RIGHT << "\" height=\""
        << H - TOP - BOTTOM << "\" fill=\"none\" stroke=\"black\"/>\n"
        << "<text x=\"" << num((LEFT + W - RIGHT) / 2) << "\" y=\"" << H - 15
        << "\" text-anchor=\"middle\">render seconds (cumulative)</text>\n"
        << "<text transform=\"translate(20 " << num((TOP + H - BOTTOM) / 2)
        << ") rotate(-90)\" text-anchor=\"middle\">relMSE (eps " << REL_EPS << ")</text>\n"
        << "<text x=\"" << num((LEFT + W - RIGHT) / 2) << "\" y=\"18\" text-anchor=\"middle\">"
        << escape(report.scene) << ", " << report.width << "x" << report.height << "</text>\n";
    svg << "<clipPath id=\"plot\"><rect x=\"" << LEFT << "\" y=\"" << TOP << "\" width=\"" << W - LEFT - RIGHT
        << "\" height=\"" << H - TOP - BOTTOM << "\"/></clipPath>\n";

    // Slope -1 guide (the unbiased Monte Carlo rate) through the default configuration's first point.
    if (!report.curves.empty() && !report.curves[0].steps.empty()) {
        const ConvergeStep& a = report.curves[0].steps.front();
        if (a.seconds > 0 && a.errors.relmse > 0) {
            const double t1 = std::pow(10.0, x.hi), t0 = std::pow(10.0, x.lo);
            const double k = a.seconds * a.errors.relmse;
            svg << "<line clip-path=\"url(#plot)\" x1=\"" << num(x.to_pixel(t0)) << "\" y1=\"" << num(y.to_pixel(k / t0))
                << "\" x2=\"" << num(x.to_pixel(t1)) << "\" y2=\"" << num(y.to_pixel(k / t1))
                << "\" stroke=\"#555\" stroke-dasharray=\"6 4\"/>\n";
        }
    }
    double legend_y = TOP + 10;
    auto legend = [&](const std::string& colour, const std::string& label, bool dashed) {
        svg << "<line x1=\"" << W - RIGHT + 12 << "\" y1=\"" << num(legend_y) << "\" x2=\"" << W - RIGHT + 40
            << "\" y2=\"" << num(legend_y) << "\" stroke=\"" << colour << "\" stroke-width=\"2\""
            << (dashed ? " stroke-dasharray=\"6 4\"" : "") << "/>\n<text x=\"" << W - RIGHT + 46 << "\" y=\""
            << num(legend_y + 4) << "\">" << escape(label) << "</text>\n";
        legend_y += 18;
    };
    for (size_t i = 0; i < report.curves.size(); ++i) {
        const std::string colour = COLOURS[i % std::size(COLOURS)];
        std::string points;
        for (const ConvergeStep& st : report.curves[i].steps)
            if (st.seconds > 0 && st.errors.relmse > 0) {
                const std::string p = num(x.to_pixel(st.seconds)) + "," + num(y.to_pixel(st.errors.relmse));
                points += p + " ";
                svg << "<circle cx=\"" << num(x.to_pixel(st.seconds)) << "\" cy=\"" << num(y.to_pixel(st.errors.relmse))
                    << "\" r=\"2.5\" fill=\"" << colour << "\"/>\n";
            }
        svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\" points=\"" << points << "\"/>\n";
        legend(colour, report.curves[i].name, false);
    }
    legend("#555", "slope -1", true);
    svg << "</svg>\n";
    write_file_atomically(file, [&](const std::filesystem::path& temp) {
        std::ofstream out(temp, std::ios::binary);
        out << svg.str();
        if (!out) throw IoError(temp.string() + ": cannot write");
    });
}

}  // namespace fh
