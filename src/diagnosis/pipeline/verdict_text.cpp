// geartopo diagnosis — the one place where a diagnosis becomes sentences (stages.hpp, decision.hpp): every record's
// text and the verdict paragraph composed from the Diagnosis' records. The console, the report, the verdict string and
// Python all print these. Units as printed: µm, µrad, s, min.
#include "stages.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <stdexcept>

namespace geartopo::diagnosis {

std::string_view to_string(Reason r) {
  switch (r) {
  case Reason::implausible_value: return "implausible_value";
  case Reason::implausible_change: return "implausible_change";
  case Reason::implausible_wave: return "implausible_wave";
  case Reason::more_than_noise: return "more_than_noise";
  case Reason::not_significant: return "not_significant";
  case Reason::explains_less: return "explains_less";
  case Reason::at_end_of_range: return "at_end_of_range";
  case Reason::not_determined: return "not_determined";
  case Reason::parts_cancel: return "parts_cancel";
  case Reason::ambiguous: return "ambiguous";
  case Reason::element_kept_out: return "element_kept_out";
  case Reason::reference_in_doubt: return "reference_in_doubt";
  }
  return "unknown";
}

double Decision::number(std::string_view key) const {
  for (const auto& [k, v] : numbers)
    if (k == key) return v;
  throw std::out_of_range(fmt::format("decision {}: no number '{}'", to_string(reason), key));
}

std::vector<double> Decision::all(std::string_view key) const {
  std::vector<double> out;
  for (const auto& [k, v] : numbers)
    if (k == key) out.push_back(v);
  return out;
}

namespace {

/// The χ² test of a more_than_noise record, without the words around it: "Σr²/σ² = 412 > 320, the χ² limit for 250
/// degrees of freedom at 0.0005".
std::string noise_test_text(const Decision& d) {
  return fmt::format("{}{:.0f} > {:.0f}, the χ² limit for {:.0f} degrees of freedom at {:g}",
                     d.test == "surface" ? "its quadratic surface per flank: Σ/σ² = " : "Σr²/σ² = ", d.number("statistic"),
                     d.number("limit"), d.number("dof"), d.number("false_alarm"));
}

} // namespace

std::string to_text(const Decision& d) {
  switch (d.reason) {
  case Reason::implausible_value:
    return fmt::format("{} = {} is outside its plausible range [{}, {}]{}", d.subject,
                       text::with_uncertainty(d.number("value"), d.number("sd")), d.number("plausible_lo"),
                       d.number("plausible_hi"), d.number("at_end_of_range") != 0.0 ? " (at the end of the fit's range)" : "");
  case Reason::implausible_change:
    return fmt::format("{} over the job is {:.3g} {}, beyond the {:g} {} a machine element plausibly changes", d.subject,
                       d.number("reach"), d.unit, d.number("limit"), d.unit);
  case Reason::implausible_wave:
    return fmt::format("a wave of {:.3g} µm is beyond the {:g} µm a dressed wheel plausibly carries",
                       d.number("amplitude_um"), d.number("limit_um"));
  case Reason::more_than_noise: return "what it leaves is more than noise (" + noise_test_text(d) + ")";
  case Reason::not_significant:
    return fmt::format("not significant (ΔBIC {:.1f}, not below −{:g})", d.number("delta_bic"), d.number("threshold"));
  case Reason::explains_less: return fmt::format("explains less than {}, which is no explanation", d.names.at(0));
  case Reason::at_end_of_range:
    return fmt::format("{} = {:g} is at the end of its allowed range [{:g}, {:g}]: no measured value", d.subject,
                       d.number("value"), d.number("lo"), d.number("hi"));
  case Reason::not_determined: return d.subject + " is not determined by these data";
  case Reason::parts_cancel: {
    std::string named;
    const auto parts = d.all("part_rms_um");
    for (size_t e = 0; e < d.names.size() && e < parts.size(); ++e)
      named += fmt::format("{}{} ({:.2f} µm RMS)", e == 0 ? "" : " and ", d.names[e], parts[e]);
    return fmt::format("its parts cancel: {} leave {:.2f} µm RMS together", named, d.number("together_rms_um"));
  }
  case Reason::ambiguous:
    return fmt::format("ambiguous between {} and {}: measure more (the plan) before adding either", d.names.at(0),
                       d.names.at(1));
  case Reason::element_kept_out:
    return fmt::format("The best machine element, {} (ΔBIC {:.1f}), leaves a field {} can leave too, within {:g} of it: "
                       "{} stays named.",
                       d.subject, d.number("delta_bic"), d.names.at(0), d.number("threshold"), d.names.at(0));
  case Reason::reference_in_doubt:
    return fmt::format(
        "The measurement looks evaluated against the drawing: it has no design_um column and nobody said what it is "
        "measured from, so it was read as measured against the bare involute, and its residual is largely minus the "
        "scene's design ({:.2f} µm RMS as read, {:.2f} µm against the drawing; the design {:.2f} µm RMS, set-up terms "
        "removed, noise {:.2f} µm). If the measuring machine evaluated against the drawing, say so: "
        "--measured-against design (measurement.measured_against: design in the scene, or a design_um column), and "
        "diagnose again; if the values are from the bare involute, the gear lacks its drawing's modifications: "
        "--measured-against involute. What follows rests on the file as read.",
        d.number("residual_rms_um"), d.number("against_drawing_rms_um"), d.number("design_rms_um"), d.number("noise_um"));
  }
  return {};
}

std::string to_text(const DeterminedGrowth& g) {
  return fmt::format("{} grew by {} µm between {:.1f} and {:.1f} min", g.axis, text::with_uncertainty(g.value_um, g.sd_um, true),
                     g.from_s / 60.0, g.to_s / 60.0);
}

std::string to_text(const AssumedValue& a) {
  return fmt::format("{}.{} = {:g} (assumed: the effect's default; the scene gives none and the flanks cannot identify it)",
                     a.effect, a.key, a.value);
}

std::string to_text(const ResidualPattern& p) {
  std::string text;
  for (size_t k = 0; k < p.largest.size(); ++k) {
    const auto& s = p.largest[k];
    text += p.flanks > 1 ? fmt::format("{}{} {:+.2f} µm on average (from {:+.2f} to {:+.2f})", k ? " and " : "", s.pattern,
                                       s.mean_um, s.lo_um, s.hi_um)
                         : fmt::format("{}{} {:+.2f} µm", k ? " and " : "", s.pattern, s.mean_um);
  }
  if (!p.largest.empty()) text += fmt::format(" over the {} measured flank{}", p.flanks, p.flanks > 1 ? "s" : "");
  std::string teeth;
  for (const auto& [tooth, rms] : p.tooth_rms_um) teeth += fmt::format("{}{}: {:.2f}", teeth.empty() ? "" : ", ", tooth, rms);
  return text + (text.empty() ? "RMS" : "; RMS") + " by tooth " + teeth + " µm.";
}

std::vector<Decision> Diagnosis::decisions() const {
  std::vector<Decision> out;
  if (reference_in_doubt) out.push_back(*reference_in_doubt);
  for (const auto* d : {&nearest_rejection, &beyond_trigger})
    if (*d) out.push_back(**d);
  if (element_kept_out) out.push_back(*element_kept_out);
  if (nearest_element && nearest_element->rejection) out.push_back(*nearest_element->rejection);
  if (remainder_excess) out.push_back(*remainder_excess);
  if (withheld && withheld->reason != Reason::reference_in_doubt) out.push_back(*withheld);
  return out;
}

namespace stages {
namespace {

/// "x_growth_um = 9.1 ± 1.2, time_constant_s = 600 ± 90": the fitted values of a candidate with their 1σ, each rounded
/// to its uncertainty (GUM §7.2.6, text::with_uncertainty).
std::string parameters_text(const Candidate& c) {
  std::string s;
  for (size_t e = 0; e < c.effects.size(); ++e)
    for (const auto& p : c.parameters[e])
      if (p.fitted)
        s += fmt::format("{}{}{}{}", s.empty() ? "" : ", ", c.effects.size() > 1 ? c.effects[e].type + "." : std::string(),
                         p.key, p.determined ? " = " + text::with_uncertainty(p.value, p.uncertainty)
                                             : std::string(" not determined by these data"));
  return s;
}

/// The first `shown` names joined by ", ", then how many more there are and where they are listed: a class of 49
/// equivalent components is a line, not a page.
std::string listed_briefly(const std::vector<std::string>& names, std::size_t shown) {
  if (names.size() <= shown) return fmt::format("{}", fmt::join(names, ", "));
  return fmt::format("{} and {} more (all in diagnosis.json, \"equivalent\")",
                     fmt::join(names.begin(), names.begin() + static_cast<long>(shown), ", "), names.size() - shown);
}

/// The recommendation in words: the teeth and grid to measure, the ΔBIC gap expected after both explanations are
/// refitted (each way), the best few teeth with where on them the difference is largest.
std::string plan_sentence(const MeasurementPlan& plan, std::size_t named, double target, bool nested = false) {
  if (plan.teeth.empty()) return "Every tooth is measured already; more rows or columns per flank would be needed.";
  std::string teeth;
  for (size_t k = 0; k < std::min(named, plan.teeth.size()); ++k) {
    const auto& t = plan.teeth[k];
    teeth += fmt::format("{}tooth {} ({:.1f}σ; largest {:.2f} µm on its {} flank, row {}, column {})", k ? ", " : "",
                         t.tooth, t.separation_sigma, t.max_difference_um, t.flank == Flank::Left ? "left" : "right",
                         t.row, t.col);
  }
  const auto best = [](const std::vector<double>& v) {
    return static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin()) + 1;
  };
  const auto& r = plan.recommended;
  // One explanation inside the other: if the smaller is right the larger refits its data and trails by its extra
  // parameters' penalty only — and is then no rival, its partner no longer pointed to (diagnose, "Ambiguity").
  const std::string nested_note =
      nested ? " — a few, the penalty of the larger one's extra parameters, if the smaller one is right: then the "
               "partner is no longer pointed to"
             : "";
  return fmt::format("{} teeth {} with {}, both flanks ({} points): after both explanations are "
                     "refitted, the expected ΔBIC gap is {:.0f} if {} is right and {:.0f} if {} is ({}{:g} needed{}; "
                     "{:.1f}σ apart before the refit, in units of the {:.2f} µm noise). Largest differences: {}; the "
                     "profile row {} and face-width column {} of the {} × {} grid carry most of it.",
                     r.resolves ? "To decide, measure" : "No option tried is expected to decide; the closest: measure",
                     fmt::join(r.teeth, ","), what_to_measure(r), r.points, r.delta_bic_if_first, plan.first,
                     r.delta_bic_if_second, plan.second, r.resolves ? "≥ " : "< ", target, nested_note,
                     r.separation_before_refit_sigma, plan.noise_um, teeth, best(plan.row_separation_sigma),
                     best(plan.col_separation_sigma), plan.rows, plan.cols);
}

/// Whether another measurement would tell an equivalence class's members apart, from their plan: the teeth that
/// would, or that no tooth of this gear on the grids tried does (their fields are alike there too).
std::string equivalence_sentence(const MeasurementPlan& plan) {
  const auto& r = plan.recommended;
  if (plan.teeth.empty()) return "Every tooth is measured: no measurement on this gear separates them.";
  if (!r.resolves)
    return fmt::format("No measurement of the other teeth tried separates them either (at most {:.1f}σ apart on "
                       "teeth {} with {}; expected ΔBIC gap {:.0f} / {:.0f} after the refit): "
                       "their fields are alike on every flank of this gear.",
                       r.separation_before_refit_sigma, fmt::join(r.teeth, ","), what_to_measure(r), r.delta_bic_if_first,
                       r.delta_bic_if_second);
  return fmt::format("Measuring teeth {} with {} would separate them (expected ΔBIC gap {:.0f} "
                     "if {} is right, {:.0f} if {} is).",
                     fmt::join(r.teeth, ","), what_to_measure(r), r.delta_bic_if_first, plan.first, r.delta_bic_if_second,
                     plan.second);
}

std::string setup_text(const Diagnosis& d) {
  if (d.setup.rotation_identified)
    return fmt::format("Set-up (not process physics, fitted alongside): thickness {} µm, rotation {} µrad. ",
                       text::with_uncertainty(d.setup.thickness_um, d.setup.thickness_sd_um, true),
                       text::with_uncertainty(d.setup.rotation_urad, d.setup.rotation_sd_urad, true));
  return fmt::format("Set-up (not process physics, fitted alongside): offset {} µm (one flank side "
                     "measured: thickness and rotation not separable). ",
                     text::with_uncertainty(d.setup.thickness_um, d.setup.thickness_sd_um, true));
}

std::string nearest_text(const Diagnosis& d) {
  if (!d.nearest) return "none fitted";
  return fmt::format("{} ({}; ΔBIC {:.1f}, leaving {:.2f} µm RMS) — rejected: {}", d.nearest->name(),
                     parameters_text(*d.nearest), d.nearest->delta_bic, d.nearest->rms_after_um,
                     d.nearest_rejection ? to_text(*d.nearest_rejection) : std::string());
}

std::string noise_text(const Diagnosis& d) {
  return fmt::format("noise {:.2f} µm{}", d.noise_um, d.noise_estimated ? ", estimated" : "");
}

/// A machine element named: what it is, its look-alikes in the library, its equivalence class, its rivals.
std::string element_verdict(const Diagnosis& d, const DiagnoseOptions& o) {
  const Candidate& h = *d.chosen;
  std::string v = fmt::format("Not an effect of the library: {} (ΔBIC {:.1f}). ", h.description, h.delta_bic);
  if (!h.library_equivalent.empty())
    v += fmt::format("On these flanks the library's {} can leave the same field (≥ {:.0f} % of it lies in what {} can "
                     "do): the same deviation through another element. ",
                     fmt::join(h.library_equivalent, ", "), 100.0 * o.alike_share,
                     h.library_equivalent.size() == 1 ? "that explanation" : "each of them");
  if (!h.equivalent.empty())
    v += fmt::format("Equivalent on these flanks (the data cannot tell them apart; one class): {}. {} ",
                     listed_briefly(h.equivalent, 8), d.equivalent_plan ? equivalence_sentence(*d.equivalent_plan) : "");
  if (!d.rivals.empty()) {
    std::string rivals;
    for (const auto& c : d.rivals) rivals += (rivals.empty() ? "" : ", ") + fmt::format("{} (ΔBIC {:.1f})", c.name(), c.delta_bic);
    v += fmt::format("Ambiguous between {} and {}, within ΔBIC {:g} with a different field: these data cannot tell them "
                     "apart; not added to the scene. {} ",
                     h.name(), rivals, o.bic_threshold,
                     d.plan ? plan_sentence(*d.plan, o.plan_teeth_named, o.plan_target_delta_bic) : "");
  }
  return v + fmt::format("Adding it takes the residual (set-up removed) from {:.2f} to {:.2f} µm RMS ({}). Nearest "
                         "library explanation: {}.",
                         d.rms_before_setup_um, d.rms_after_um, noise_text(d), nearest_text(d));
}

/// A library explanation named: missing, or the best of the ambiguous ones with the plan that would decide.
std::string library_verdict(const Diagnosis& d, const DiagnoseOptions& o) {
  std::string v;
  if (!d.rivals.empty()) {
    std::string names = d.chosen->name();
    for (const auto& r : d.rivals) names += " and " + r.name();
    const bool nested = d.chosen->nested_in(d.rivals.front()) || d.rivals.front().nested_in(*d.chosen);
    v = setup_text(d) + fmt::format("Ambiguous between {} (ΔBIC {:.1f} vs {:.1f}, within {:g}): these data cannot tell "
                                    "them apart. {} ",
                                    names, d.chosen->delta_bic, d.rivals.front().delta_bic, o.bic_threshold,
                                    d.plan ? plan_sentence(*d.plan, o.plan_teeth_named, o.plan_target_delta_bic, nested)
                                           : "");
  }
  return v + (d.rivals.empty() ? setup_text(d) : std::string()) +
         fmt::format("{}: {}. Adding it takes the residual (set-up removed) from {:.2f} to {:.2f} µm RMS ({}).",
                     d.rivals.empty() ? "Missing" : "Best of them", d.chosen->name(), d.rms_before_setup_um,
                     d.rms_after_um, noise_text(d));
}

/// A fit the evidence favoured over what is named (chosen or nearest) but plausibility refused: said aloud, with why.
std::string better_but_rejected(const Diagnosis& d) {
  const Candidate* named = d.chosen ? &*d.chosen : d.nearest ? &*d.nearest : nullptr;
  const auto better = std::min_element(d.ranked.begin(), d.ranked.end(), [](const Candidate& a, const Candidate& b) {
    return a.delta_bic < b.delta_bic;
  });
  if (!named || better == d.ranked.end() || better->name() == named->name() || !better->rejection ||
      !(better->delta_bic < named->delta_bic))
    return {};
  return fmt::format(" {} fits better (ΔBIC {:.1f}) but was rejected: {}.", better->name(), better->delta_bic,
                     to_text(*better->rejection));
}

} // namespace

std::string verdict_text(const Diagnosis& d, const DiagnoseOptions& o) {
  std::string v = d.reference_in_doubt ? to_text(*d.reference_in_doubt) + " " : std::string();
  if (d.chosen && d.beyond_library) {
    v += setup_text(d) + element_verdict(d, o);
  } else if (!d.chosen && d.unexplained) {
    v += setup_text(d) +
        fmt::format("Unexplained: no effect of the library, alone or in a pair, explains the residual ({:.2f} µm RMS "
                    "with the set-up removed, against {:.2f} µm noise: {}). What is left unexplained: {} Nearest library "
                    "explanation: {}.{} Nothing is added to the scene.",
                    d.rms_before_setup_um, d.noise_um, d.remainder_excess ? noise_test_text(*d.remainder_excess) : "",
                    d.residual_pattern ? to_text(*d.residual_pattern) : "", nearest_text(d),
                    d.nearest_element ? fmt::format(" Nearest machine element: {} (ΔBIC {:.1f}, leaving {:.2f} µm RMS) — "
                                                    "{}.",
                                                    d.nearest_element->description, d.nearest_element->delta_bic,
                                                    d.nearest_element->rms_after_um, to_text(*d.nearest_element->rejection))
                                      : "");
  } else if (!d.chosen) {
    v += setup_text(d) + fmt::format("No effect of the library is needed: with the set-up terms removed, the residual "
                                    "({:.2f} µm RMS) is noise ({:.2f} µm{}). Nearest library explanation: {}.",
                                    d.rms_before_setup_um, d.noise_um, d.noise_estimated ? ", estimated" : "",
                                    nearest_text(d));
  } else {
    v += library_verdict(d, o);
  }
  v += better_but_rejected(d);
  if (d.withheld && d.rivals.empty())
    v += d.withheld->reason == Reason::reference_in_doubt
             ? std::string(" Not added to the scene until the measurement's reference is said.")
             : " Not added to the scene: " + to_text(*d.withheld) + ".";
  if (!d.determined.empty()) {
    std::vector<std::string> fixed;
    for (const auto& g : d.determined) fixed.push_back(to_text(g));
    v += fmt::format(" Its single values are not all determined; the data fix: {}.", fmt::join(fixed, "; "));
  }
  if (d.element_kept_out) v += " " + to_text(*d.element_kept_out);
  if (!d.assumed.empty()) {
    std::vector<std::string> lines;
    for (const auto& a : d.assumed) lines.push_back(to_text(a));
    v += " Set-up values assumed, not measured: " + fmt::format("{}", fmt::join(lines, "; ")) + ".";
  }
  return v;
}

} // namespace stages
} // namespace geartopo::diagnosis
