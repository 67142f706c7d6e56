"""ONE bibliography for roughstick: every citation the package writes comes from here.

Functions put ``references=cite(...)`` in the CF attributes of what they return, and their
docstrings cite the same keys; ``tests/_core/test_references.py`` checks that no other module
holds a citation string and that every DOI written anywhere in the repository is one of these
(cf. SurfaceTopography's ``Support/Bibliography.py``).

Each entry records whether its DOI was checked against a bibliographic record (``checked``);
the ones that were not say so in ``note``.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Reference", "BIBLIOGRAPHY", "PAPER", "cite", "reference"]


@dataclass(frozen=True)
class Reference:
    """One bibliography entry (a full citation and its DOI)."""

    authors: str
    title: str
    source: str
    year: int
    doi: str | None
    checked: bool = True
    note: str = ""

    def __str__(self) -> str:
        doi = f", doi:{self.doi}" if self.doi else ""
        return f"{self.authors}, {self.title}, {self.source}{doi}"

    @property
    def url(self) -> str | None:
        """``https://doi.org/<doi>`` (None for a book without DOI)."""
        return f"https://doi.org/{self.doi}" if self.doi else None


#: Key of the paper roughstick implements.
PAPER = "hoang2015"

BIBLIOGRAPHY: dict[str, Reference] = {
    # --- the paper and its sequel -------------------------------------------------------------
    "hoang2015": Reference(
        # the journal's author list (J. Comput. Appl. Math. record; the paper's text carries none)
        "T.-V. Hoang, L. Wu, S. Paquay, A.C. Obreja, R.C. Voicu, R. Müller, J.-C. Golinval, L. Noels",
        "A probabilistic model for predicting the uncertainties of the humid stiction phenomenon "
        "on hard materials",
        "J. Comput. Appl. Math. 289 (2015) 173-195", 2015, "10.1016/j.cam.2015.02.022",
    ),
    "hoang2017": Reference(
        "T.-V. Hoang, L. Wu, S. Paquay, J.-C. Golinval, M. Arnst, L. Noels",
        "A computational stochastic multiscale methodology for MEMS structures involving adhesive "
        "contact",
        "Tribology International 110 (2017) 401-425", 2017, "10.1016/j.triboint.2016.10.007",
        note="authors, journal, year, pages and DOI checked against a bibliographic record; the "
             "volume (110) was not",
    ),
    # --- experiments ---------------------------------------------------------------------------
    "delrio2007": Reference(
        "F.W. DelRio, M.L. Dunn, L.M. Phinney, C.J. Bourdon, M.P. de Boer",
        "Rough surface adhesion in the presence of capillary condensation",
        "Appl. Phys. Lett. 90 (2007) 163104", 2007, "10.1063/1.2723658",
    ),
    "deboer1998": Reference(
        "M.P. de Boer, P.J. Clews, B.K. Smith, T.A. Michalske",
        "Adhesion of polysilicon microbeams in controlled humidity ambients",
        "MRS Proc. 518 (1998) 131", 1998, "10.1557/PROC-518-131",
    ),
    "mastrangelo1993": Reference(
        "C.H. Mastrangelo, C.H. Hsu",
        "Mechanical stability and adhesion of microstructures under capillary forces. II. Experiments",
        "J. Microelectromech. Syst. 2 (1993) 44-55", 1993, "10.1109/84.232594",
    ),
    # --- single-asperity contact ---------------------------------------------------------------
    "hertz1882": Reference(
        "H. Hertz", "Ueber die Berührung fester elastischer Körper",
        "J. reine angew. Math. 92 (1882) 156-171", 1882, "10.1515/crll.1882.92.156",
    ),
    "johnson1985": Reference(
        "K.L. Johnson", "Contact Mechanics", "Cambridge University Press (1985)", 1985,
        "10.1017/CBO9781139171731",
    ),
    "jkr1971": Reference(
        "K.L. Johnson, K. Kendall, A.D. Roberts", "Surface energy and the contact of elastic solids",
        "Proc. R. Soc. Lond. A 324 (1971) 301-313", 1971, "10.1098/rspa.1971.0141",
    ),
    "dmt1975": Reference(
        "B.V. Derjaguin, V.M. Muller, Yu.P. Toporov",
        "Effect of contact deformations on the adhesion of particles",
        "J. Colloid Interface Sci. 53 (1975) 314-326", 1975, "10.1016/0021-9797(75)90018-1",
    ),
    "maugis1992": Reference(
        "D. Maugis", "Adhesion of spheres: the JKR-DMT transition using a Dugdale model",
        "J. Colloid Interface Sci. 150 (1992) 243-269", 1992, "10.1016/0021-9797(92)90285-T",
    ),
    "kim1998": Reference(
        "K.-S. Kim, R.M. McMeeking, K.L. Johnson",
        "Adhesion, slip, cohesive zones and energy fluxes for elastic spheres in contact",
        "J. Mech. Phys. Solids 46 (1998) 243-266", 1998, "10.1016/S0022-5096(97)00070-7",
    ),
    # --- rough surfaces: statistics and statistical contact ------------------------------------
    "greenwood1966": Reference(
        "J.A. Greenwood, J.B.P. Williamson", "Contact of nominally flat surfaces",
        "Proc. R. Soc. Lond. A 295 (1966) 300-319", 1966, "10.1098/rspa.1966.0242",
    ),
    "nayak1971": Reference(
        "P.R. Nayak", "Random process model of rough surfaces",
        "J. Lubr. Technol. 93 (1971) 398-407", 1971, "10.1115/1.3451608",
    ),
    "greenwood2006": Reference(
        "J.A. Greenwood", "A simplified elliptic model of rough surface contact",
        "Wear 261 (2006) 191-200", 2006, "10.1016/j.wear.2005.09.031", checked=False,
        note="DOI as given in the GW issue; not checked against a record here",
    ),
    "shinozuka1991": Reference(
        "M. Shinozuka, G. Deodatis", "Simulation of stochastic processes by spectral representation",
        "Appl. Mech. Rev. 44 (1991) 191-204", 1991, "10.1115/1.3119501",
    ),
    # --- non-Gaussian surfaces: height distributions and how to impose them -------------------
    "johnson1949": Reference(
        "N.L. Johnson", "Systems of frequency curves generated by methods of translation",
        "Biometrika 36 (1949) 149-176", 1949, "10.1093/biomet/36.1-2.149",
        note="DOI checked against independent citing records (volume 36, issue 1/2, pages; "
             "JSTOR 2332539)",
    ),
    "schreiber1996": Reference(
        "T. Schreiber, A. Schmitz", "Improved surrogate data for nonlinearity tests",
        "Phys. Rev. Lett. 77 (1996) 635-638", 1996, "10.1103/PhysRevLett.77.635",
        note="DOI checked against the authors' arXiv record (chao-dyn/9909041)",
    ),
    "perez-rafols2019": Reference(
        "F. Pérez-Ràfols, A. Almqvist",
        "Generating randomly rough surfaces with given height probability distribution and power "
        "spectrum",
        "Tribol. Int. 131 (2019) 591-604", 2019, "10.1016/j.triboint.2018.11.020",
        note="DOI, volume and pages checked against a library catalogue record",
    ),
    "shields2011": Reference(
        "M.D. Shields, G. Deodatis, P. Bocchini",
        "A simple and efficient methodology to approximate a general non-Gaussian stationary "
        "stochastic process by a translation process",
        "Probab. Eng. Mech. 26 (2011) 511-519", 2011, "10.1016/j.probengmech.2011.04.003",
        note="DOI checked against independent citing records (volume 26, issue 4, pages)",
    ),
    # --- boundary-element reference (Tamaas) ---------------------------------------------------
    "polonsky1999": Reference(
        "I.A. Polonsky, L.M. Keer",
        "A numerical method for solving rough contact problems based on the multi-level "
        "multi-summation and conjugate gradient techniques",
        "Wear 231 (1999) 206-219", 1999, "10.1016/S0043-1648(99)00113-1",
    ),
    "rey2017": Reference(
        "V. Rey, G. Anciaux, J.-F. Molinari",
        "Normal adhesive contact on rough surfaces: efficient algorithm for FFT-based BEM resolution",
        "Comput. Mech. 60 (2017) 69-81", 2017, "10.1007/s00466-017-1392-5",
    ),
    "frerot2020": Reference(
        "L. Frérot, G. Anciaux, V. Rey, S. Pham-Ba, J.-F. Molinari",
        "Tamaas: a library for elastic-plastic contact of periodic rough surfaces",
        "J. Open Source Softw. 5 (2020) 2121", 2020, "10.21105/joss.02121",
    ),
    # --- statistics ----------------------------------------------------------------------------
    "au2001": Reference(
        "S.-K. Au, J.L. Beck",
        "Estimation of small failure probabilities in high dimensions by subset simulation",
        "Probab. Eng. Mech. 16 (2001) 263-277", 2001, "10.1016/S0266-8920(01)00019-4",
        note="DOI checked against independent citing records (journal, volume, issue 4, pages)",
    ),
    "cotter2013": Reference(
        "S.L. Cotter, G.O. Roberts, A.M. Stuart, D. White",
        "MCMC methods for functions: modifying old algorithms to make them faster",
        "Stat. Sci. 28 (2013) 424-446", 2013, "10.1214/13-STS421",
        note="DOI checked against independent citing records (volume 28, issue 3, pages)",
    ),
    "papaioannou2015": Reference(
        "I. Papaioannou, W. Betz, K. Zwirglmaier, D. Straub",
        "MCMC algorithms for subset simulation",
        "Probab. Eng. Mech. 41 (2015) 89-103", 2015, "10.1016/j.probengmech.2015.06.006",
        checked=False, note="DOI not found in any record consulted; citing records disagree on "
                            "the first page (89 or 83)",
    ),
    "wilson1927": Reference(
        "E.B. Wilson", "Probable inference, the law of succession, and statistical inference",
        "J. Am. Stat. Assoc. 22 (1927) 209-212", 1927, "10.1080/01621459.1927.10502953",
    ),
    "clopper1934": Reference(
        "C.J. Clopper, E.S. Pearson",
        "The use of confidence or fiducial limits illustrated in the case of the binomial",
        "Biometrika 26 (1934) 404-413", 1934, "10.1093/biomet/26.4.404",
    ),
    "kunsch1989": Reference(
        "H.R. Künsch", "The jackknife and the bootstrap for general stationary observations",
        "Ann. Statist. 17 (1989) 1217-1241", 1989, "10.1214/aos/1176347265",
        note="DOI checked against independent citing records (volume 17, issue 3); citing "
             "records disagree on the last page (1241 or 1261)",
    ),
    "peherstorfer2018": Reference(
        "B. Peherstorfer, K. Willcox, M. Gunzburger",
        "Survey of multifidelity methods in uncertainty propagation, inference, and optimization",
        "SIAM Rev. 60 (2018) 550-591", 2018, "10.1137/16M1082469",
    ),
    "sarndal1992": Reference(
        "C.-E. Särndal, B. Swensson, J. Wretman",
        "Model Assisted Survey Sampling (two-phase sampling and difference estimators, ch. 9)",
        "Springer (1992)", 1992, None,
    ),
    "woodruff1952": Reference(
        "R.S. Woodruff", "Confidence intervals for medians and other position measures",
        "J. Am. Stat. Assoc. 47 (1952) 635-646", 1952, None,
        note="cited without DOI: none was checked against a bibliographic record",
    ),
    "conover1999": Reference(
        "W.J. Conover", "Practical Nonparametric Statistics, 3rd ed. (order-statistic intervals, §3.2)",
        "Wiley (1999)", 1999, None,
    ),
}


def reference(key: str) -> Reference:
    """The entry ``key`` of :data:`BIBLIOGRAPHY` (``KeyError`` naming the known keys)."""
    try:
        return BIBLIOGRAPHY[key]
    except KeyError:
        raise KeyError(f"no bibliography entry {key!r}; known keys: {sorted(BIBLIOGRAPHY)}") from None


def cite(*items) -> str:
    """The CF ``references`` string for ``items``: full citations joined by ``"; "``.

    Each item is a key of :data:`BIBLIOGRAPHY` or a ``(key, detail)`` pair whose detail (the
    equations or sections used) is appended in parentheses.

    Examples
    --------
    >>> from roughstick._core.references import cite
    >>> cite(("hoang2015", "Eq. 37"))[:40]
    'T.-V. Hoang, L. Wu, S. Paquay, A.C. Obre'
    >>> cite("nayak1971")
    'P.R. Nayak, Random process model of rough surfaces, J. Lubr. Technol. 93 (1971) 398-407, doi:10.1115/1.3451608'
    """
    parts = []
    for item in items:
        key, detail = (item, None) if isinstance(item, str) else item
        text = str(reference(key))
        parts.append(f"{text} ({detail})" if detail else text)
    return "; ".join(parts)
