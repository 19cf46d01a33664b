fn main() {
    let path = std::env::args().nth(1).unwrap();
    let scene = lux::usd::load_stage(std::path::Path::new(&path), 1.0).unwrap();
    for m in &scene.materials {
        let Some(g) = &m.graph else {
            println!("{}: no graph", m.path);
            continue;
        };
        println!(
            "{} model {} nodes {} notes {:?}",
            m.path,
            g.model,
            g.nodes.len(),
            g.notes
        );
        let mut tc = lux::render::material::graph::TextureCache::new();
        let mut w = Vec::new();
        let s = lux::render::material::graph::GraphShader::compile(g, &mut tc, &mut w);
        println!(
            "  instrs {} value instrs {} lambert {:?} warnings {:?}",
            s.instruction_count(),
            s.value_instruction_count(),
            s.constant_lambert(),
            w
        );
        if std::env::var("DUMP").is_ok() {
            println!("{:#?}", s);
        }
        break;
    }
}
