"""Each export format's lobe by the format's own definition, written from its specification, independently of
vk-render's Rust export: the file read back by the format's own parser (pygltflib, MaterialX's Python package,
Mitsuba 3 itself; pbrt has no Python package, so a tokenizer of its scene text), its parameters evaluated as
the format defines them. Directions are unit vectors in the surface's frame (normal +z), arrays of shape (N, 3);
each function returns f_r, shape (N, 3).

`course_g=True` evaluates the file's parameters with the course's Smith-Schlick G (k = (r + 1)^2 / 8, r the
square root of the file's alpha) and Schlick's Fresnel from the file's own Fresnel at normal incidence: where
the format's structure is ours, that lobe is ours to float precision, and a wrong mapping (alpha for r, a
remapped roughness, a colour in the wrong place) shows as a large difference. With `course_g=False` the
format's own G and Fresnel: the difference is the models', which the tests bound."""

import math
import re
import xml.etree.ElementTree as ElementTree

import numpy as np


# --- microfacet pieces -------------------------------------------------------------------------------------

def half_vector(wi, wo):
    h = wi + wo
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def ggx_d(cos_h, alpha):
    """Trowbridge-Reitz (GGX) D, isotropic."""
    a2 = alpha * alpha
    c2 = cos_h * cos_h
    return a2 / (math.pi * (c2 * (a2 - 1.0) + 1.0) ** 2)


def smith_lambda(cos_t, alpha):
    """Smith's Lambda for GGX (Heitz 2014, eq. 72)."""
    tan2 = np.maximum(1.0 - cos_t * cos_t, 0.0) / (cos_t * cos_t)
    return (np.sqrt(1.0 + alpha * alpha * tan2) - 1.0) / 2.0


def g_height_correlated(cos_i, cos_o, alpha):
    return 1.0 / (1.0 + smith_lambda(cos_i, alpha) + smith_lambda(cos_o, alpha))


def g_separable(cos_i, cos_o, alpha):
    return 1.0 / ((1.0 + smith_lambda(cos_i, alpha)) * (1.0 + smith_lambda(cos_o, alpha)))


def g_course(cos_i, cos_o, alpha):
    """The course's Smith-Schlick G with Karis's k = (r + 1)^2 / 8, r = sqrt(alpha)."""
    k = (math.sqrt(alpha) + 1.0) ** 2 / 8.0
    return cos_i / (cos_i * (1 - k) + k) * cos_o / (cos_o * (1 - k) + k)


def schlick(f0, cos):
    return f0 + (1.0 - f0) * (1.0 - cos)[:, None] ** 5


def fresnel_conductor(eta, k, cos):
    """The unpolarised Fresnel reflectance of a conductor eta + i k (from the air), per channel."""
    cos = np.clip(cos, 0.0, 1.0)[:, None]
    n = np.asarray(eta, complex) + 1j * np.asarray(k, float)
    sin2 = 1.0 - cos * cos
    cos_t = np.sqrt(1.0 - sin2 / (n * n))
    r_parallel = (n * cos - cos_t) / (n * cos + cos_t)
    r_perpendicular = (cos - n * cos_t) / (cos + n * cos_t)
    return ((np.abs(r_parallel) ** 2 + np.abs(r_perpendicular) ** 2) / 2.0).real


def microfacet(wi, wo, alpha, fresnel, g):
    """D G F / (4 cos_i cos_o), `fresnel(cos_d)` of the half vector's angle, `g` one of the G functions."""
    h = half_vector(wi, wo)
    cos_i, cos_o = wi[:, 2], wo[:, 2]
    d = ggx_d(h[:, 2], alpha)
    return (d * g(cos_i, cos_o, alpha) / (4.0 * cos_i * cos_o))[:, None] * fresnel(np.sum(wo * h, axis=1))


def course_or_own(course_g, own_g, f0, own_fresnel):
    """The G and the Fresnel to evaluate with: the course's (Schlick from the format's F0) or the format's."""
    if course_g:
        return g_course, lambda cos: schlick(np.asarray(f0, float), cos)
    return own_g, own_fresnel


# --- glTF 2.0 ----------------------------------------------------------------------------------------------

def gltf(path, wi, wo, course_g=False):
    """glTF 2.0 Appendix B: mix(dielectric, metal, metallic); metal = GGX (alpha = roughness^2, V the
    height-correlated Smith's) with Schlick's Fresnel of baseColor; dielectric = KHR_materials_specular's
    fresnel_mix: (1 - specular max(F)) Lambert(baseColor) + specular F GGX, F Schlick's of
    min(((ior - 1) / (ior + 1))^2 specularColor, 1) (KHR_materials_ior's ior, default 1.5)."""
    import pygltflib

    document = pygltflib.GLTF2().load(str(path))
    assert document.asset.version == "2.0"
    (material,) = document.materials
    pbr = material.pbrMetallicRoughness
    base = np.array(pbr.baseColorFactor[:3], float)
    metallic, alpha = pbr.metallicFactor, pbr.roughnessFactor ** 2
    extensions = material.extensions or {}
    for name in extensions:
        assert name in document.extensionsUsed, f"{name} not in extensionsUsed"
    specular = extensions.get("KHR_materials_specular", {})
    weight = specular.get("specularFactor", 1.0)
    colour = np.array(specular.get("specularColorFactor", [1.0, 1.0, 1.0]), float)
    ior = extensions.get("KHR_materials_ior", {}).get("ior", 1.5)
    dielectric_f0 = np.minimum(((ior - 1.0) / (ior + 1.0)) ** 2 * colour, 1.0)

    g, metal_fresnel = course_or_own(course_g, g_height_correlated, base, lambda cos: schlick(base, cos))
    metal = microfacet(wi, wo, alpha, metal_fresnel, g)
    h = half_vector(wi, wo)
    fr = schlick(dielectric_f0, np.sum(wo * h, axis=1))
    dielectric = (1.0 - weight * fr.max(axis=1))[:, None] * base / math.pi
    if weight > 0:
        dielectric = dielectric + weight * microfacet(wi, wo, alpha, lambda cos: schlick(dielectric_f0, cos), g)
    return (1.0 - metallic) * dielectric + metallic * metal


# --- MaterialX: Standard Surface and OpenPBR ---------------------------------------------------------------

def materialx_shader(path):
    """The document read and validated by MaterialX against its standard libraries: the shader node's
    category and a function of an input's name giving its value (the node's, else its definition's default)."""
    import MaterialX as mx

    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    libraries = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), libraries)
    document.importLibrary(libraries)
    valid, message = document.validate()
    assert valid, message
    (material,) = [n for n in document.getMaterialNodes()]
    (shader,) = mx.getShaderNodes(material)
    definition = shader.getNodeDef()
    assert definition is not None, f"{shader.getCategory()} has no definition in MaterialX's libraries"

    def value(name, document=document):  # the document kept alive: its elements are orphaned without it
        given = shader.getInput(name)
        if given is None:
            given = definition.getActiveInput(name)
        v = given.getValue()
        return np.array(v.asTuple(), float) if hasattr(v, "asTuple") else float(v)

    return shader.getCategory(), value


def mx_oren_nayar(wi, wo, roughness):
    """MaterialX 1.39's oren_nayar_diffuse_bsdf without energy compensation (pbrlib's mx_oren_nayar_diffuse):
    the qualitative model with sigma = roughness, A + B max(0, s) / max(cos_i, cos_o), s = wi.wo - cos_i
    cos_o; times 1 / pi."""
    sigma2 = roughness * roughness
    a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33)
    b = 0.45 * sigma2 / (sigma2 + 0.09)
    s = np.sum(wi * wo, axis=1) - wi[:, 2] * wo[:, 2]
    return (a + b * np.where(s > 0, s / np.maximum(wi[:, 2], wo[:, 2]), 0.0)) / math.pi


FUJII_1 = 0.5 - 2.0 / (3.0 * math.pi)
FUJII_2 = 2.0 / 3.0 - 28.0 / (15.0 * math.pi)


def fujii_albedo(cos, roughness):
    """The directional albedo of Fujii's improved Oren-Nayar lobe."""
    a = 1.0 / (1.0 + FUJII_1 * roughness)
    sin = np.sqrt(np.maximum(0.0, 1.0 - cos * cos))
    g = sin * (np.arccos(np.clip(cos, -1, 1)) - sin * cos) + 2.0 * ((sin / cos) * (1.0 - sin ** 3) - sin) / 3.0
    return a + roughness * a * g / math.pi


def eon(wi, wo, roughness, colour):
    """OpenPBR's energy-preserving Oren-Nayar (Portsmouth et al. 2025, as MaterialX 1.39's
    oren_nayar_diffuse_bsdf with energy_compensation): Fujii's single-scattering lobe colour A (1 + r s / max(cos_i,
    cos_o)) (s itself where negative) plus a multiple-scattering lobe from the albedos; times 1 / pi."""
    cos_i, cos_o = wi[:, 2], wo[:, 2]
    s = np.sum(wi * wo, axis=1) - cos_i * cos_o
    stinv = np.where(s > 0, s / np.maximum(cos_i, cos_o), s)
    a = 1.0 / (1.0 + FUJII_1 * roughness)
    single = colour * (a * (1.0 + roughness * stinv))[:, None]
    average = a * (1.0 + FUJII_2 * roughness)
    multiple_colour = colour * colour * average / (1.0 - colour * max(0.0, 1.0 - average))
    eps = np.finfo(np.float32).eps
    multiple = multiple_colour * (np.maximum(eps, 1.0 - fujii_albedo(cos_o, roughness))
                                  * np.maximum(eps, 1.0 - fujii_albedo(cos_i, roughness))
                                  / max(eps, 1.0 - average))[:, None]
    return (single + multiple) / math.pi


def artistic_ior(reflectivity, edge_colour):
    """Gulbrandsen 2014's eta and k of a conductor from its reflectivity r and edge colour g (MaterialX's
    artistic_ior node)."""
    r = np.clip(reflectivity, 0.0, 0.99)
    n_min = (1.0 - r) / (1.0 + r)
    n_max = (1.0 + np.sqrt(r)) / (1.0 - np.sqrt(r))
    eta = n_max * (1.0 - edge_colour) + n_min * edge_colour
    k2 = ((eta + 1.0) ** 2 * r - (eta - 1.0) ** 2) / (1.0 - r)
    return eta, np.sqrt(np.maximum(k2, 0.0))


def f82_tint(f0, tint, cos):
    """OpenPBR's metal Fresnel (Hoffman 2019, F82-tint): Schlick's minus a (1 - cos)^6 cos term that makes it
    tint times Schlick's at cos = 1/7; tint 1 leaves Schlick's."""
    mu_bar = 1.0 / 7.0
    schlick_bar = f0 + (1.0 - f0) * (1.0 - mu_bar) ** 5
    a = schlick_bar * (1.0 - tint) / (mu_bar * (1.0 - mu_bar) ** 6)
    return schlick(f0, cos) - a * (cos * (1.0 - cos) ** 6)[:, None]


def materialx(path, wi, wo, course_g=False):
    """Standard Surface or OpenPBR Surface with no coat, sheen, subsurface, transmission or thin film:
    (1 - metalness) dielectric base + metalness metal, the metal GGX (alpha = specular_roughness^2, MaterialX's
    height-correlated Smith G), Standard Surface's Fresnel the artistic conductor's of base base_color and
    specular specular_color, OpenPBR's F82-tint of base_weight base_color and specular_color, weighed by
    specular_weight. The dielectric base is a specular layer over the diffuse lobe; its layer reflects nothing
    with an IOR of 1 (the only one the exporter writes, checked), leaving base base_color Oren-Nayar (Standard
    Surface) or EON (OpenPBR)."""
    category, value = materialx_shader(path)
    if category == "standard_surface":
        zero = ["coat", "sheen", "subsurface", "transmission", "thin_film_thickness", "emission"]
        weight, colour, metalness = value("base"), value("base_color"), value("metalness")
        diffuse_roughness, ior = value("diffuse_roughness"), value("specular_IOR")
        reflectivity = weight * colour
        eta, k = artistic_ior(reflectivity, value("specular") * value("specular_color"))
        own_fresnel = lambda cos: fresnel_conductor(eta, k, cos)  # noqa: E731
        f0 = fresnel_conductor(eta, k, np.ones(1))[0]
        metal_weight = 1.0
        diffuse = mx_oren_nayar(wi, wo, diffuse_roughness)[:, None] * weight * colour
    else:
        assert category == "open_pbr_surface", category
        zero = ["coat_weight", "fuzz_weight", "subsurface_weight", "transmission_weight", "thin_film_weight",
                "emission_luminance"]
        weight, colour, metalness = value("base_weight"), value("base_color"), value("base_metalness")
        ior, tint = value("specular_ior"), value("specular_color")
        f0 = weight * colour
        own_fresnel = lambda cos: f82_tint(f0, tint, cos)  # noqa: E731
        metal_weight = value("specular_weight")
        diffuse = eon(wi, wo, value("base_diffuse_roughness"), weight * colour)
    for name in zero:
        assert value(name) == 0.0, f"{name} {value(name)}"
    assert ior == 1.0, f"the dielectric layer's IOR {ior}: only 1 (no reflection) is evaluated here"
    alpha = value("specular_roughness") ** 2
    g, fresnel = course_or_own(course_g, g_height_correlated, f0, own_fresnel)
    metal = metal_weight * microfacet(wi, wo, alpha, fresnel, g)
    return (1.0 - metalness) * diffuse + metalness * metal


# --- Mitsuba 3 ---------------------------------------------------------------------------------------------

def mitsuba_bsdf(path):
    """The file's BSDF as Mitsuba 3 loads it: a scene that includes the file and puts its BSDF on a shape."""
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    (bsdf,) = ElementTree.parse(path).getroot().findall("bsdf")
    scene = mi.load_string(
        f'<scene version="3.0.0"><include filename="{path}"/>'
        f'<shape type="rectangle"><ref id="{bsdf.get("id")}"/></shape></scene>'
    )
    return scene.shapes()[0].bsdf()


def mitsuba(path, wi, wo):
    """f_r by Mitsuba 3's own BSDF.eval (which returns f_r cos(theta_o)), in scalar_rgb."""
    import drjit as dr
    import mitsuba as mi

    bsdf = mitsuba_bsdf(path)
    context = mi.BSDFContext()
    values = np.zeros((len(wi), 3))
    for row, (i, o) in enumerate(zip(wi, wo)):
        interaction = dr.zeros(mi.SurfaceInteraction3f)
        interaction.n = mi.Normal3f(0, 0, 1)
        interaction.sh_frame = mi.Frame3f(interaction.n)
        interaction.wi = mi.Vector3f(*map(float, o))
        values[row] = np.array(bsdf.eval(context, interaction, mi.Vector3f(*map(float, i)))) / float(i[2])
    return values


def mitsuba_by_definition(path, wi, wo, course_g=False):
    """Mitsuba 3's diffuse, roughconductor and blendbsdf by their documentation: reflectance / pi; GGX with
    `alpha` itself, the separable Smith G (G1(wi) G1(wo)) and the conductor Fresnel of eta + i k; (1 - weight)
    first + weight second."""

    def evaluate(element):
        kind = element.get("type")
        params = {p.get("name"): p.get("value") for p in element if p.tag != "bsdf"}
        rgb = lambda name: np.array([float(v) for v in params[name].split(",")])  # noqa: E731
        if kind == "diffuse":
            return np.tile(rgb("reflectance") / math.pi, (len(wi), 1))
        if kind == "roughconductor":
            assert params["distribution"] == "ggx"
            eta, k = rgb("eta"), rgb("k")
            f0 = fresnel_conductor(eta, k, np.ones(1))[0]
            g, fresnel = course_or_own(course_g, g_separable, f0, lambda cos: fresnel_conductor(eta, k, cos))
            return microfacet(wi, wo, float(params["alpha"]), fresnel, g)
        assert kind == "blendbsdf", kind
        first, second = element.findall("bsdf")
        weight = float(params["weight"])
        return (1.0 - weight) * evaluate(first) + weight * evaluate(second)

    (bsdf,) = ElementTree.parse(path).getroot().findall("bsdf")
    return evaluate(bsdf)


# --- pbrt-v4 -----------------------------------------------------------------------------------------------

def pbrt_materials(path):
    """The named materials of a pbrt-v4 scene text: {name: {"type": ..., "TYPE NAME": [values...]}}."""
    tokens = re.findall(r'"[^"]*"|\[|\]|[^\s\[\]"]+', re.sub(r"#[^\n]*", "", path.read_text()))
    materials, at = {}, 0
    while at < len(tokens):
        assert tokens[at] == "MakeNamedMaterial", tokens[at]
        name, at = tokens[at + 1].strip('"'), at + 2
        params = {}
        while at < len(tokens) and tokens[at].startswith('"'):
            key, at = tokens[at].strip('"'), at + 1
            assert tokens[at] == "[", key
            end = tokens.index("]", at)
            params[key] = [t.strip('"') for t in tokens[at + 1:end]]
            at = end + 1
        materials[name] = params
    return materials


def pbrt(path, wi, wo, course_g=False, name=None):
    """pbrt-v4's diffuse, conductor and mix by their definitions: reflectance / pi; TrowbridgeReitz with alpha =
    roughness (sqrt(roughness) unless remaproughness is false), the height-correlated Smith G, and the Fresnel
    of a conductor of eta and k (of a `reflectance` r: eta 1, k = 2 sqrt(r) / sqrt(1 - r), r clamped to 0.9999); mix
    picks its second material with probability amount, (1 - amount) first + amount second in expectation."""
    materials = pbrt_materials(path)

    def evaluate(named):
        params = materials[named]
        kind = params["string type"][0]
        rgb = lambda key: np.array([float(v) for v in params[key]])  # noqa: E731
        if kind == "diffuse":
            return np.tile(rgb("rgb reflectance") / math.pi, (len(wi), 1))
        if kind == "conductor":
            roughness = float(params["float roughness"][0])
            alpha = roughness if params.get("bool remaproughness", ["true"])[0] == "false" else math.sqrt(roughness)
            if "rgb eta" in params:
                eta, k = rgb("rgb eta"), rgb("rgb k")
            else:
                r = np.clip(rgb("rgb reflectance"), 0.0, 0.9999)
                eta, k = np.ones(3), 2.0 * np.sqrt(r) / np.sqrt(1.0 - r)
            f0 = fresnel_conductor(eta, k, np.ones(1))[0]
            g, fresnel = course_or_own(course_g, g_height_correlated, f0, lambda cos: fresnel_conductor(eta, k, cos))
            return microfacet(wi, wo, alpha, fresnel, g)
        assert kind == "mix", kind
        first, second = params["string materials"]
        amount = float(params["float amount"][0])
        return (1.0 - amount) * evaluate(first) + amount * evaluate(second)

    # The material the file defines last is the one it names for use (the others are its parts).
    return evaluate(name or list(materials)[-1])
