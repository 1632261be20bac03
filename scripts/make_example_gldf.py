#!/usr/bin/env python3
"""Build scenes/gldf/example_downlight.gldf from data shipped in the tree (run from the repo root):
photometry host/data/photometry/erco_downlight_lm63-1986_onevalperline.ies and
lithonia_esg_iesna91_commas.ies (sources and licences in host/data/photometry/SOURCES.md), the
spectrum CIE illuminant LED-B1 (host/data/illuminants/led_b1.csv, CIE 015:2018) as a
`spectrum/text` file. Two variants, one emitter each, one fixed light source with that spectrum.
Element names follow the GLDF 1.0.0-rc.3 documentation on gldf.io."""
import csv, zipfile, sys

out = sys.argv[1] if len(sys.argv) > 1 else "scenes/gldf/example_downlight.gldf"
rows = [r for r in csv.reader(l for l in open("host/data/illuminants/led_b1.csv") if not l.startswith("#"))][1:]
spectrum = "".join(f"{r[0]}\t{r[1]}\n" for r in rows)
xml = """<?xml version="1.0" encoding="UTF-8"?>
<Root xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="https://gldf.io/xsd/gldf/1.0.0-rc.3/gldf.xsd">
  <Header>
    <Manufacturer>spectrace example (not a real product)</Manufacturer>
    <FormatVersion major="1" minor="0" pre-release="3" />
    <CreatedWithApplication>scripts/make_example_gldf.py</CreatedWithApplication>
    <GldfCreationTimeCode>2026-12-06T21:30:00Z</GldfCreationTimeCode>
    <UniqueGldfId>6f1d3c1e-5a7b-4c1e-9d2a-000000000001</UniqueGldfId>
  </Header>
  <GeneralDefinitions>
    <Files>
      <File id="ldtDownlight" contentType="ldc/ies" type="localFileName">erco_downlight.ies</File>
      <File id="ldtSpot" contentType="ldc/ies" type="localFileName">lithonia_esg.ies</File>
      <File id="spectrumFile" contentType="spectrum/text" type="localFileName">led_b1.txt</File>
    </Files>
    <Photometries>
      <Photometry id="photometryDownlight"><PhotometryFileReference fileId="ldtDownlight" /></Photometry>
      <Photometry id="photometrySpot"><PhotometryFileReference fileId="ldtSpot" /></Photometry>
    </Photometries>
    <Spectrums>
      <Spectrum id="spectrumLed"><SpectrumFileReference fileId="spectrumFile" /></Spectrum>
    </Spectrums>
    <LightSources>
      <FixedLightSource id="lightSourceLed">
        <Name><Locale language="en">LED, CIE LED-B1 spectrum</Locale></Name>
        <SpectrumReference spectrumId="spectrumLed" />
        <ColorInformation>
          <ColorRenderingIndex>82</ColorRenderingIndex>
          <CorrelatedColorTemperature>2735</CorrelatedColorTemperature>
        </ColorInformation>
      </FixedLightSource>
    </LightSources>
    <Emitters>
      <Emitter id="emitterDownlight">
        <FixedLightEmitter>
          <PhotometryReference photometryId="photometryDownlight" />
          <LightSourceReference fixedLightSourceId="lightSourceLed" />
          <RatedLuminousFlux>1300</RatedLuminousFlux>
        </FixedLightEmitter>
      </Emitter>
      <Emitter id="emitterSpot">
        <FixedLightEmitter>
          <PhotometryReference photometryId="photometrySpot" />
          <LightSourceReference fixedLightSourceId="lightSourceLed" />
        </FixedLightEmitter>
      </Emitter>
    </Emitters>
  </GeneralDefinitions>
  <ProductDefinitions>
    <ProductMetaData>
      <UniqueProductId>example-downlight</UniqueProductId>
      <Name><Locale language="en">Example downlight (ERCO and Lithonia photometry, CIE LED-B1 spectrum)</Locale></Name>
    </ProductMetaData>
    <Variants>
      <Variant id="downlight">
        <Name><Locale language="en">Downlight</Locale></Name>
        <Geometry><EmitterReference emitterId="emitterDownlight" /></Geometry>
      </Variant>
      <Variant id="spot">
        <Name><Locale language="en">Spot</Locale></Name>
        <Geometry><EmitterReference emitterId="emitterSpot" /></Geometry>
      </Variant>
    </Variants>
  </ProductDefinitions>
</Root>
"""
with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
    z.writestr("product.xml", xml)
    z.write("host/data/photometry/erco_downlight_lm63-1986_onevalperline.ies", "ldc/erco_downlight.ies")
    z.write("host/data/photometry/lithonia_esg_iesna91_commas.ies", "ldc/lithonia_esg.ies")
    z.writestr("spectrum/led_b1.txt", spectrum)
print("wrote", out)
