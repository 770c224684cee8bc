// cost_error_plot.cpp: the bench's cost-error plot (see cost_error_plot.h).
#include "cost_error_plot.h"

#include <algorithm>
#include <cmath>

#include "figure.h"

namespace retroprism::plot {

namespace {

// The points no other point beats in both cost and error, by cost.
std::vector<const CostErrorPoint*> pareto_front(const std::vector<const CostErrorPoint*>& pts) {
    std::vector<const CostErrorPoint*> front;
    for (const CostErrorPoint* p : pts) {
        bool dominated = false;
        for (const CostErrorPoint* q : pts)
            if (q != p && q->ns <= p->ns && q->error <= p->error &&
                (q->ns < p->ns || q->error < p->error))
                dominated = true;
        if (!dominated) front.push_back(p);
    }
    std::sort(front.begin(), front.end(),
              [](const CostErrorPoint* a, const CostErrorPoint* b) { return a->ns < b->ns; });
    return front;
}

} // namespace

OIIO::ImageBuf cost_error_figure(const std::vector<CostErrorPoint>& points, double baselineNs) {
    std::vector<const CostErrorPoint*> pts;
    for (const CostErrorPoint& p : points)
        if (p.error > 0) pts.push_back(&p);
    const std::vector<const CostErrorPoint*> front = pareto_front(pts);
    Figure fig;
    fig.title = "retroprism: ns per eval vs relative L1 error against the double reference "
                "(Pareto front in orange)";
    fig.title_size = 17;
    fig.panel_width = 870;
    fig.panel_height = 500;
    fig.pad_left = 60;
    fig.pad_right = 30; // room for the last x label, centred on the edge
    fig.top = 20;
    fig.pad_top = 40;
    fig.pad_bottom = 30;
    fig.x_label = "ns per evaluation (log)";
    Panel pan;
    // 10 ns to 1 us: every row is within; the labels of the most accurate rows stack downward
    // from about 1e-7, so the error axis reaches 1e-10 to hold them above the axis's labels.
    pan.x.lo = 1;
    pan.x.hi = 3;
    pan.x.log = true;
    pan.x.label = [](double d, double) { return fmt("%.0f ns", std::pow(10.0, d)); };
    pan.x.label_size = 15;
    pan.y.lo = -10;
    pan.y.hi = 0;
    pan.y.log = true;
    pan.y.step = 2;
    pan.y.label = [](double d, double) { return fmt("1e%.0f", d); };
    pan.y.label_size = 15;
    Series line;
    line.color = kLobeColor[1];
    for (const CostErrorPoint* p : front) {
        line.x.push_back(p->ns);
        line.y.push_back(p->error);
    }
    // Points from the largest error down, so that their labels stack downward.
    std::vector<const CostErrorPoint*> byPos = pts;
    std::sort(byPos.begin(), byPos.end(), [](const CostErrorPoint* a, const CostErrorPoint* b) {
        return a->error != b->error ? a->error > b->error : a->ns < b->ns;
    });
    Series dots;
    dots.points = true;
    dots.width = 5;
    for (const CostErrorPoint* p : byPos) {
        const bool onFront = std::find(front.begin(), front.end(), p) != front.end();
        dots.x.push_back(p->ns);
        dots.y.push_back(p->error);
        dots.colors.push_back(onFront ? kLobeColor[1] : kLobeColor[0]);
        dots.labels.push_back(p->name);
    }
    pan.series = {line, dots};
    if (baselineNs > 0) {
        Marker base;
        base.x = baselineNs;
        base.color = kLobeColor[2];
        base.dashed = false;
        base.label = "MaterialX retro GGX";
        pan.markers.push_back(base);
        // The targets of the trade: fast within 2x, exact within 6x.
        for (double k : {2.0, 6.0}) {
            Marker m;
            m.x = k * baselineNs;
            m.color = kDimText;
            m.label = fmt("%.0fx", k);
            m.label_bottom = true;
            m.label_size = 13;
            pan.markers.push_back(m);
        }
    }
    fig.panels.push_back(pan);
    Text text("retroprism bench");
    return render(fig, text);
}

} // namespace retroprism::plot
