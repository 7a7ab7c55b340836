//! The egui panels: bodies, shape mix, fitting methods, simulation controls,
//! overlays, live figures and their plot; and the 3D view's mouse input
//! (orbit, zoom, click to select).

use std::time::Duration;

use bvol::volumes::{ObbMethod, SphereMethod};
use egui::{Color32, Pos2, Rect, Sense, Stroke, Ui, vec2};
use glam::Vec2;

use crate::app::{App, FrameRecord};

/// Colours of the plotted series.
const COLLISION_COLOR: Color32 = Color32::from_rgb(255, 120, 90);
const PHYSICS_COLOR: Color32 = Color32::from_rgb(120, 200, 255);
const FRAME_COLOR: Color32 = Color32::from_rgb(230, 230, 230);
const TOUCHING_COLOR: Color32 = Color32::from_rgb(140, 230, 120);

/// Lays the whole UI out and returns the rectangle (in points) left for the
/// 3D view, after handling the mouse over it.
pub fn show(ui: &mut Ui, app: &mut App) -> Rect {
    egui::Panel::left("controls").default_size(300.0).resizable(true).show(ui, |ui| {
        egui::ScrollArea::vertical().show(ui, |ui| controls(ui, app));
    });
    let mut view = Rect::NOTHING;
    egui::CentralPanel::no_frame().show(ui, |ui| {
        view = ui.max_rect();
        let response = ui.allocate_rect(view, Sense::click_and_drag());
        view_input(ui, app, &response);
        if let Some(id) = app.selected {
            ui.painter().text(
                view.left_top() + vec2(10.0, 10.0),
                egui::Align2::LEFT_TOP,
                format!("selected: body {} (click empty space to clear)", id.index()),
                egui::FontId::proportional(14.0),
                Color32::WHITE,
            );
        }
    });
    view
}

/// Orbit on drag, zoom on scroll, select on click.
fn view_input(ui: &Ui, app: &mut App, response: &egui::Response) {
    let rect = response.rect;
    if response.dragged() {
        let d = response.drag_delta();
        app.camera.orbit(Vec2::new(d.x, d.y));
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            app.camera.zoom(scroll);
        }
    }
    if response.clicked()
        && let Some(p) = response.interact_pointer_pos()
    {
        let at = Vec2::new((p.x - rect.left()) / rect.width(), (p.y - rect.top()) / rect.height());
        app.pick(rect.width() / rect.height().max(1.0), at);
    }
}

fn controls(ui: &mut Ui, app: &mut App) {
    ui.heading("bvol · falling objects");
    bodies(ui, app);
    ui.separator();
    simulation(ui, app);
    ui.separator();
    overlays(ui, app);
    ui.separator();
    fitting(ui, app);
    ui.separator();
    figures(ui, app);
    ui.separator();
    plot(ui, app);
    selection(ui, app);
    if !app.log.is_empty() {
        ui.separator();
        ui.label("Messages");
        for line in &app.log {
            ui.colored_label(Color32::from_rgb(255, 140, 110), line);
        }
    }
}

fn bodies(ui: &mut Ui, app: &mut App) {
    let n = app.sim.bodies().len();
    let awake = app.sim.bodies().iter().filter(|b| !b.asleep).count();
    ui.label(format!("{n} bodies ({awake} awake)"));
    ui.horizontal(|ui| {
        if ui.button("Add 100").clicked() {
            app.add_bodies(100);
        }
        if ui.button("Add 1 000").clicked() {
            app.add_bodies(1000);
        }
        if ui.button("Reset").clicked() {
            app.reset();
        }
    });
    ui.collapsing("Shape mix", |ui| {
        for (entry, weight) in app.library.entries.iter().zip(&mut app.settings.mix) {
            ui.add(egui::Slider::new(weight, 0.0..=5.0).text(&entry.name));
        }
    });
}

fn simulation(ui: &mut Ui, app: &mut App) {
    let s = &mut app.settings;
    ui.horizontal(|ui| {
        ui.checkbox(&mut s.paused, "Pause");
        if ui.add_enabled(s.paused, egui::Button::new("Step")).clicked() {
            s.step_once = true;
        }
    });
    ui.add(egui::Slider::new(&mut s.speed, 0.1..=4.0).text("steps per frame"));
}

fn overlays(ui: &mut Ui, app: &mut App) {
    let s = &mut app.settings;
    ui.label("Overlays");
    ui.checkbox(&mut s.show_spheres, "Bounding spheres");
    ui.checkbox(&mut s.show_obbs, "Oriented boxes");
    ui.checkbox(&mut s.show_contacts, "Contacts and normals");
    ui.checkbox(&mut s.show_tree, "Tree nodes by depth");
    if s.show_tree {
        let (mut first, mut last) = s.tree_depths;
        ui.add(egui::Slider::new(&mut first, 0..=40).text("from depth"));
        ui.add(egui::Slider::new(&mut last, 0..=40).text("to depth"));
        s.tree_depths = (first, last.max(first));
    }
}

fn fitting(ui: &mut Ui, app: &mut App) {
    let mut fit = app.settings.fit;
    ui.label("Fitting methods");
    egui::ComboBox::from_label("sphere").selected_text(fit.sphere.name()).show_ui(ui, |ui| {
        for m in SphereMethod::ALL {
            ui.selectable_value(&mut fit.sphere, *m, m.name());
        }
    });
    egui::ComboBox::from_label("OBB").selected_text(fit.obb.name()).show_ui(ui, |ui| {
        for m in ObbMethod::ALL {
            ui.selectable_value(&mut fit.obb, *m, m.name());
        }
    });
    if fit != app.settings.fit {
        app.set_fit(fit);
    }
}

fn ms(d: Duration) -> String {
    format!("{:.2}", d.as_secs_f64() * 1e3)
}

fn figures(ui: &mut Ui, app: &App) {
    let Some(last) = app.history.back() else { return };
    let recent = app.history.iter().rev().take(60);
    let (frames, total) = recent.fold((0, Duration::ZERO), |(n, t), r| (n + 1, t + r.frame));
    let fps = if total.is_zero() { 0.0 } else { frames as f64 / total.as_secs_f64() };
    ui.label(format!("{fps:.1} frames per second"));
    let s = &last.stats;
    egui::Grid::new("stages").striped(true).show(ui, |ui| {
        ui.label("stage");
        ui.label("pairs");
        ui.label("ms");
        ui.end_row();
        for (name, pairs, time) in [
            ("world bounds", s.moved, s.bounds_time),
            ("broadphase candidates", s.candidates, s.broadphase_time),
            ("after spheres", s.after_spheres, s.spheres_time),
            ("after OBBs", s.after_obbs, s.obbs_time),
            ("touching", s.touching, s.narrow_time),
        ] {
            ui.label(name);
            ui.label(pairs.to_string());
            ui.label(ms(time));
            ui.end_row();
        }
    });
    ui.label(format!(
        "collision {} ms · physics {} ms · render {} ms · frame {} ms",
        ms(last.collision),
        ms(last.physics),
        ms(last.render),
        ms(last.frame)
    ));
}

/// Frame, physics and collision times (ms, left scale) and touching pairs
/// (right scale) over the kept history.
fn plot(ui: &mut Ui, app: &App) {
    let width = ui.available_width().max(100.0);
    let (rect, _) = ui.allocate_exact_size(vec2(width, 110.0), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(24));
    let records: Vec<&FrameRecord> = app.history.iter().collect();
    if records.len() < 2 {
        return;
    }
    let ms_of = |d: Duration| d.as_secs_f32() * 1e3;
    let top_ms = records.iter().map(|r| ms_of(r.frame)).fold(1.0, f32::max);
    let top_pairs = records.iter().map(|r| r.stats.touching as f32).fold(1.0, f32::max);
    let x = |i: usize| rect.left() + rect.width() * i as f32 / (crate::app::HISTORY - 1) as f32;
    let y = |v: f32, top: f32| rect.bottom() - rect.height() * (v / top).min(1.0);
    let series = |value: &dyn Fn(&FrameRecord) -> f32, top: f32, color: Color32| {
        let points: Vec<Pos2> =
            records.iter().enumerate().map(|(i, r)| Pos2::new(x(i), y(value(r), top))).collect();
        painter.add(egui::Shape::line(points, Stroke::new(1.2, color)));
    };
    series(&|r| ms_of(r.frame), top_ms, FRAME_COLOR);
    series(&|r| ms_of(r.physics), top_ms, PHYSICS_COLOR);
    series(&|r| ms_of(r.collision), top_ms, COLLISION_COLOR);
    series(&|r| r.stats.touching as f32, top_pairs, TOUCHING_COLOR);
    ui.horizontal_wrapped(|ui| {
        ui.colored_label(FRAME_COLOR, format!("frame (0-{top_ms:.0} ms)"));
        ui.colored_label(PHYSICS_COLOR, "physics");
        ui.colored_label(COLLISION_COLOR, "collision");
        ui.colored_label(TOUCHING_COLOR, format!("touching (0-{top_pairs:.0})"));
    });
}

fn selection(ui: &mut Ui, app: &App) {
    let Some(id) = app.selected else { return };
    let world = app.sim.world();
    ui.separator();
    ui.label(format!("Body {}", id.index()));
    if let Some(body) = app.sim.bodies().iter().find(|b| b.id == id) {
        ui.label(format!("shape: {}", app.library.entries[body.shape].name));
        ui.label(format!("position: {:.2}", body.position));
        ui.label(format!(
            "speed: {:.2} m/s{}",
            body.velocity.length(),
            if body.asleep { " (asleep)" } else { "" }
        ));
    }
    if let (Ok(sphere), Ok(obb)) = (world.world_sphere(id), world.world_obb(id)) {
        ui.label(format!("sphere: radius {:.3}, volume {:.3}", sphere.radius, sphere.volume()));
        ui.label(format!("OBB: half extents {:.3}, volume {:.3}", obb.half_extents, obb.volume()));
    }
    let contacts = app.sim.contacts().iter().filter(|(a, b, _)| *a == id || *b == id);
    for (a, b, contact) in contacts {
        let other = if *a == id { b } else { a };
        ui.label(format!(
            "touches {}: depth {:.4}, {} points",
            other.index(),
            contact.depth,
            contact.points().len()
        ));
    }
}
