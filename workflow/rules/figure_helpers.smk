# figure name -> (short target name, kind of input file, library modules it draws with)
FIGURES = {
    "fig01_orbits": ("fig1", "orbits"),
    "fig02_action_frequency": ("fig2", "orbits"),
    "fig03_poles": ("fig3", "orbits"),
    "fig04_contributions": ("fig4", "theory"),
    "fig05_dielectric": ("fig5", "theory"),
    "fig06_landau_lenard_balescu": ("fig6", "theory"),
    "fig07_closed_forms": ("fig7", "closed_forms"),
    "fig08_dj2": ("fig8", "md_full"),
    "fig09_md_thermal": ("fig9", "md_theory"),
    "fig10_md_corehalo": ("fig10", "md_theory"),
}


FIGURE_CAPTIONS = {
    "fig01_orbits": "Fig. 1 (fig:hmforbits): a librating orbit (kappa < 1), the separatrix "
    "(kappa = 1) and a rotating orbit (kappa > 1, both directions) of h = p^2/2 - M0 cos(theta), "
    "from the inverse angle-action map (appendix A).",
    "fig02_action_frequency": "Fig. 2 (fig:hmfactom): the action J(kappa) (eq. hmfaction), "
    "discontinuous at the separatrix, and the frequency Omega(J) (eq. hmfomega), inset Omega(kappa).",
    "fig03_poles": "Fig. 3 (fig:hmfpoles): poles of the dielectric integrand, Omega(kappa) = "
    "omega/l: two poles kappa_1 < 1 < kappa_2 for 0 < omega/l < Omega_0, one above Omega_0.",
    "fig04_contributions": "Fig. 4 (fig:hmfcontribs): normalised contribution "
    "gamma(kappa, kappa*)/D_dif(kappa) of each resonant orbit kappa* to the Lenard-Balescu "
    "diffusion coefficient (eq. hmfCEdif), thermal states M0 = 0.05 and 0.9.",
    "fig05_dielectric": "Fig. 5 (fig:eps): cosine and sine components of the dielectric tensor "
    "(eqs. hmfepscc, hmfepsss; Landau prescription), thermal (u, M0) = (-0.1, 0.728); vertical "
    "lines at Omega_0 and 2 Omega_0.",
    "fig06_landau_lenard_balescu": "Fig. 6 (fig:hmfCENCEcompare): N D_dif(kappa) with (Lenard-"
    "Balescu, eqs. hmfCEdif + hmfD) and without (Landau, eq. hmfDbare) collective effects, thermal "
    "(u, M0) = (-0.1, 0.7285) and (0.2475, 0.0632); cut near the separatrix.",
    "fig07_closed_forms": "Fig. 7 (M0.8): (a-c) eps_cc, eps_ss and N D_dif of the smooth core-halo "
    "states ch1*, ch2* against the two-step closed form (eq. hmfepscc/ss-ch, corrected); (d-f) the "
    "same for the thermal state M0 = 0.95 against appendix C (eqs. eps_cc_ap, eps_ss_ap, corrected).",
    "fig08_dj2": "Fig. 8 (fig:dj2t): <dJ^2>(dt) from MD(full) for several J0, with the linear "
    "fits (eq. hmfmddif) over the shaded window.",
    "fig09_md_thermal": "Fig. 9 (fig:hmfdiff): N D from MD against theory, thermal (u, M0) = "
    "(-0.2, 0.816), (0.0, 0.622), (0.2475, 0.063): MD(bath) vs Landau (top), MD(full) vs "
    "Lenard-Balescu (bottom); errors from the spread between seeds; grey line: separatrix.",
    "fig10_md_corehalo": "Fig. 10 (fig:hmfch): the same for the core-halo state ch2* "
    "(beta1=30, beta2=10, eta1=0.298, eta2=0.051, mu1=-0.517, mu2=0.19, M0 = 0.8).",
}


def figure_cases(name):
    spec = config["figures"][name]
    if "cases" in spec:
        return spec["cases"]
    if "case" in spec:
        return [spec["case"]]
    return list(spec.get("core_halo", [])) + [
        spec[k] for k in ("two_step", "thermal") if k in spec
    ]


def figure_inputs(wildcards):
    """Input files of one figure: {kind}_{i} for each of its cases, and the plotting library."""
    kind = FIGURES[wildcards.name][1]
    if kind == "closed_forms":
        spec = config["figures"][wildcards.name]
        smooth = list(spec["core_halo"]) + [spec["thermal"]]
        files = {f"theory_{i}": f"results/theory/{c}.nc" for i, c in enumerate(smooth)}
        files["analytic_0"] = f"results/analytic/{spec['two_step']}.nc"
        files["analytic_1"] = f"results/analytic/{spec['thermal']}.nc"
        files["lib"] = lib("plotting", "orbits")
        return files
    cases = figure_cases(wildcards.name)
    if kind == "md_full":
        files = {
            f"fit_full_{i}": f"results/fits/{c}_full.nc" for i, c in enumerate(cases)
        }
    elif kind == "md_theory":
        files = {}
        for i, c in enumerate(cases):
            files[f"fit_bath_{i}"] = f"results/fits/{c}_bath.nc"
            files[f"fit_full_{i}"] = f"results/fits/{c}_full.nc"
            files[f"theory_{i}"] = f"results/theory/{c}.nc"
    else:
        files = {f"{kind}_{i}": f"results/{kind}/{c}.nc" for i, c in enumerate(cases)}
    files["lib"] = lib("plotting", "orbits")
    return files


def figure_targets():
    return expand(
        "results/figures/{name}.{ext}",
        name=[n for n in FIGURES if n in config["figures"]],
        ext=["pdf", "png"],
    )
